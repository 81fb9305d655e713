"""The port background as physics: every pixel a surface energy balance under the ship's sky.

The paper's background (:mod:`.background`) extends one Landsat overpass through the day
with a same-day kriged met grid and a terrain regression; it exists only where such a grid
exists, and the built-in port carried its design days' climate wherever it was placed.
Here the background follows the run's one :class:`shipthermal.environment.Environment` —
the same sun, sky long-wave, air, humidity, wind, cloud and sea as the ship — at any site,
date and weather record:

* **land pixels** (vegetation, land, building, and classes users add) are layered columns
  (:mod:`.surface_classes`, :mod:`.surface_energy`): absorbed short-wave on the pixel's own
  slope and aspect, long-wave exchange with the sky it sees and with the terrain around it,
  convection, latent heat where the class evaporates, conduction into the substrate;
* **water pixels** are the weather's sea at its skin temperature (bulk + diurnal warm layer
  − cool skin, :mod:`shipthermal.environment.sea_skin`): the very sea the ship floats on;
* **terrain**: each pixel's slope and aspect (DEM or the synthetic hills) set its solar
  incidence (pvlib's plane-of-array irradiance) and its sky view ``(1 + cos s)/2``; the rest
  of its hemisphere is terrain taken at the air temperature (ASSUMPTION: no terrain
  horizon shading, no building shadows).

**Columns, not pixels.** A 1000 x 1000 scene has a million pixels but few distinct columns:
pixels are grouped by class and orientation (slope bins of :data:`SLOPE_EDGES_DEG` x 8
aspect sectors, the bin's mean slope and circular-mean aspect), and each group is solved at
:data:`ALBEDO_SAMPLES` short-wave albedos spanning its class's range; a pixel's temperature
is the linear interpolation between the two columns whose albedos bracket its own. The
surface temperature is close to linear in the albedo (the absorbed short-wave is), and the
interpolation and orientation-binning errors are measured in the tests.

**Anchoring on a scene** (Landsat, :func:`ground_from_overpass`): each land pixel's albedo
is *fitted* within its class's range so that the model reproduces the scene's LST at the
overpass instant (a labelled calibration; everything else is the class table). What the fit
cannot reach (LST hotter than the darkest or colder than the brightest allowed surface) is
the pixel's residual, carried through the day as :data:`RESIDUAL_MODES` says and reported
per class with the fitted albedos' spread. Water is never fitted: its spatial pattern at the
overpass (LST minus the scene's median water LST) is kept as a fixed anomaly on the modelled
skin temperature, and the scene's median water against the model is reported as a check of
the weather's sea temperature. Without a scene (the synthetic port, a user class raster) the
albedo is the class value (the synthetic port: with its reflectance texture) and every product
says so.
"""

from __future__ import annotations

import dataclasses
import math
import time as _time
from dataclasses import dataclass, field

import numpy as np
import pandas as pd
from numba import njit, prange
from scipy.ndimage import gaussian_filter

from shipthermal.errors import InputError, require
from shipthermal.units import DAY, HOUR

from ..parameters import RESIDUAL_MODES
from .classify import CLASS_NAMES
from .landsat import SceneGrid
from .surface_classes import SURFACE_CLASSES
from .surface_energy import (SurfaceForcing, build_columns, convection_aerodynamic,
                             longwave_incoming,
                             shortwave_on_tilted, sky_view_factor, solve_surface_energy)
from .terrain import slope_aspect

__all__ = ["GroundCover", "PhysicalBackground", "build_physical_background",
           "ground_from_synthetic", "ground_from_overpass", "broadband_albedo",
           "orientation_bins", "ALBEDO_SAMPLES", "CONDUCTANCE_SAMPLES", "SLOPE_EDGES_DEG", "RESIDUAL_MODES",
           "MAX_SCENE_DAYS", "COLUMN_STEP_S", "LONG_RECORD_DAYS", "LONG_RECORD_STEP_S",
           "land_convection"]

WATER = 1

SLOPE_EDGES_DEG = (0.0, 2.0, 5.0, 10.0, 15.0, 20.0, 25.0, 30.0, 35.0, 40.0, 50.0, 90.0)
ASPECT_SECTORS = 24
"""Orientation groups: below 2 deg of slope a pixel is solved as level ground; above, the
slope bins [deg] times 24 aspect sectors of 15 deg. Solving a pixel at its group's mean
orientation instead of its own (measured in the tests, slopes 0-40 deg at 50.9 N in July):
0.11 K mean, 1.3 K at worst (steep slopes at peak sun); with 8 sectors and 6 slope bins
it was 0.33 K and 3.1 K."""

ALBEDO_SAMPLES = 5
"""Albedos a class fitted on its albedo is solved at, evenly spanning its range."""

ALBEDO_SAMPLES_WET = 3
CONDUCTANCE_SAMPLES = 5
"""A class fitted on its wetness: 3 albedos spanning its range (the pixel's own albedo is
interpolated between them) x 5 surface conductances ``1/r_s`` evenly from its driest to its
wettest."""

DRY_RESISTANCE = 1.0e9
"""Surface resistance of a dry surface in a class that may be wet [s m-1] (no evaporation)."""

WATER_MISMATCH_K = 2.0
"""A scene's median water this far from the weather's sea skin [K] is warned about:
beyond the stated accuracy of Landsat's surface temperature (about 1.5 K) and a day's
skin effects."""

COLUMN_STEP_S = 300.0
"""Time step of the column solve [s] (the ship's default step)."""

LONG_RECORD_DAYS = 31.0
"""Records longer than this [days] keep the column forcing and surface temperatures every
:data:`LONG_RECORD_STEP_S` in float32, solved in substeps of :data:`COLUMN_STEP_S` (the
forcing linear in between; the weather is hourly, the ship's forcing tables are every
600 s too). Every 300 s in float64, a year of the synthetic port's 2 200 columns needs
1.85 GB per (time × column) array and the solve held nine (40 days of San Francisco's
TMY3 year: peak memory 2.3 GB, about 17 GB for the year); so the year takes 1.9 GB. The
surface temperatures of the 40 days moved by at most 0.61 K (99 % within 0.044 K, RMS
0.010 K)."""
LONG_RECORD_STEP_S = 600.0

MAX_SCENE_DAYS = 15.0
"""Largest distance [days] between a scene's acquisition and the simulated span for its
albedos and water pattern to stand for it. ASSUMPTION: vegetation, soil moisture and sea
surface patterns change over weeks; further apart, choose a closer scene."""

SYNTHETIC_WATER_STD_K = 0.24
SYNTHETIC_WATER_SMOOTHING_PX = 5.0
"""The synthetic port's water pattern: a Gaussian random field smoothed over 5 pixels
(150 m) with a standard deviation of 0.24 K and zero mean over the water, fixed through the
day around the weather's sea. DERIVED: the water of the real Landsat-8 scene of ``examples/real_port`` (Mersey,
2020-09-27, ST_B10) has a scene-wide standard deviation of 0.24 K and a median local
(9 x 9 pixels) standard deviation of 0.09 K; this field gives 0.24 K and about 0.1 K. Real
harbour water is never uniform, and the local SCR divides by the background's spread."""

LIANG_OLI = {2: 0.356, 4: 0.130, 5: 0.373, 6: 0.085, 7: 0.072}
LIANG_OFFSET = -0.0018
"""Broadband short-wave albedo from surface reflectances, Liang (2001), Remote Sens. Environ.
76, 213-238, Table 5 (Landsat TM/ETM+ bands 1, 3, 4, 5, 7), applied to the corresponding
OLI bands 2, 4, 5, 6, 7 (blue, red, NIR, SWIR-1, SWIR-2). SOURCED."""


def broadband_albedo(reflectance: dict) -> np.ndarray:
    """Short-wave broadband albedo [-] from OLI surface reflectances (Liang 2001).

    Parameters
    ----------
    reflectance : dict[int, ndarray]
        Surface reflectance [-] of OLI bands 2, 4, 5, 6 and 7.

    Returns
    -------
    ndarray
        ``0.356 ρ2 + 0.130 ρ4 + 0.373 ρ5 + 0.085 ρ6 + 0.072 ρ7 - 0.0018`` [-].
    """
    missing = [b for b in LIANG_OLI if b not in reflectance]
    require(not missing, "reflectance", sorted(reflectance), f"needs OLI bands {sorted(LIANG_OLI)}")
    out = sum(w * np.asarray(reflectance[b], dtype=float) for b, w in LIANG_OLI.items())
    return out + LIANG_OFFSET


# ---------------------------------------------------------------------------------------
# What is known of the ground
# ---------------------------------------------------------------------------------------
@dataclass(frozen=True, eq=False)
class Observation:
    """A thermal scene the background is anchored on.

    Attributes
    ----------
    lst : ndarray float32 (rows, cols)
        Land surface temperature [K].
    time_utc : pandas.Timestamp
        Acquisition instant (tz-aware UTC).
    source : str
        What the LST is (``"Landsat-8 L2 ST_B10, 2020-09-27 11:10 UTC"``).
    accuracy_K : float
        Stated accuracy of that LST [K].
    """

    lst: np.ndarray
    time_utc: pd.Timestamp
    source: str
    accuracy_K: float


@dataclass(frozen=True, eq=False)
class GroundCover:
    """The ground of a port scene, before any temperature.

    Attributes
    ----------
    grid : SceneGrid
    class_map : ndarray uint8 (rows, cols)
        Class codes (:data:`imaging.background.classify.CLASS_NAMES`; 1 water).
    elevation, slope_deg, aspect_deg : ndarray float32 (rows, cols)
        [m], [deg], compass azimuth of the downslope direction [deg].
    albedo : ndarray float32 (rows, cols) or None
        Short-wave albedo per pixel [-] (NaN: the class's value); None: class values.
    albedo_source : str
    origin : {"synthetic", "scene", "user"}
    label : str
        What every product says the background is.
    observation : Observation or None
        The scene to anchor on.
    water_anomaly : ndarray float32 (rows, cols) or None
        Fixed pattern of the water around the sea's skin temperature [K] (a scene's is
        taken from its LST instead).
    notes : tuple of str
    """

    grid: SceneGrid
    class_map: np.ndarray
    elevation: np.ndarray
    slope_deg: np.ndarray
    aspect_deg: np.ndarray
    albedo: np.ndarray | None
    albedo_source: str
    origin: str
    label: str
    observation: Observation | None = None
    water_anomaly: np.ndarray | None = None
    notes: tuple = ()

    def __post_init__(self):
        cm = np.asarray(self.class_map)
        require(cm.shape == tuple(self.grid.shape), "background.class_map", cm.shape,
                f"must be the scene grid's shape {tuple(self.grid.shape)}")
        for name in ("elevation", "slope_deg", "aspect_deg"):
            require(np.shape(getattr(self, name)) == cm.shape, f"background.{name}",
                    np.shape(getattr(self, name)), f"must be the scene grid's shape {cm.shape}")
        unknown = sorted(set(np.unique(cm).tolist()) - set(CLASS_NAMES))
        require(not unknown, "background.class_map", unknown,
                f"codes must be {sorted(CLASS_NAMES)} ({', '.join(CLASS_NAMES.values())})",
                "Fill unclassified pixels (code 0) or crop them away")


def ground_from_synthetic(latitude: float, longitude: float, size_px: int = 334,
                          seed: int = 2026) -> GroundCover:
    """The built-in synthetic port (:func:`.synthetic.synthetic_surface`) centred on the site.

    Classes and hills are the generator's; the albedo is the broadband albedo of its
    synthetic reflectances (:func:`broadband_albedo`), so pixels of a class differ as in a
    real scene. No temperature, no climate: the physics supplies those."""
    from .synthetic import synthetic_surface

    s = synthetic_surface(seed=seed, size_px=size_px, lat=latitude, lon=longitude)
    refl = {b: s["reflectance"][k] for k, b in enumerate((2, 3, 4, 5, 6, 7))}
    slope, aspect = slope_aspect(s["elevation"].astype(float), s["grid"].resolution)
    albedo = broadband_albedo(refl).astype(np.float32)
    albedo[s["class_map"] == WATER] = np.nan
    rng = np.random.default_rng([seed, 2])
    field_ = gaussian_filter(rng.standard_normal(s["class_map"].shape),
                             SYNTHETIC_WATER_SMOOTHING_PX, mode="wrap")
    sea = s["class_map"] == WATER
    field_ = field_ - (field_[sea].mean() if sea.any() else 0.0)   # the sea's mean is the weather's
    water = (field_ / field_.std() * SYNTHETIC_WATER_STD_K).astype(np.float32)
    lat = f"{abs(latitude):.2f} {'N' if latitude >= 0 else 'S'}"
    lon = f"{abs(longitude):.2f} {'E' if longitude >= 0 else 'W'}"
    return GroundCover(
        grid=s["grid"], class_map=s["class_map"], elevation=s["elevation"],
        slope_deg=slope.astype(np.float32), aspect_deg=aspect.astype(np.float32),
        albedo=albedo, albedo_source="synthetic reflectances (Liang 2001 broadband)",
        origin="synthetic", label=f"synthetic port (not a real place) centred on {lat} {lon}",
        water_anomaly=water,
        notes=(f"synthetic port, seed {seed}, {size_px} x {size_px} pixels of 30 m: classes, "
               f"hills, reflectances and a water pattern of {SYNTHETIC_WATER_STD_K:g} K are "
               "generated; its temperatures are physics driven by the scenario's weather",))


def ground_from_overpass(overpass, elevation=None, *, dem_note: str = "") -> GroundCover:
    """The ground of a Landsat scene (:func:`.background.build_overpass`): its classes, the
    broadband albedo of its surface reflectances, its LST to anchor on; terrain from
    ``elevation`` (a DEM on the scene grid [m]; None: level ground, said in the notes)."""
    ov = overpass
    grid = ov.grid
    cm = np.asarray(ov.class_map)
    if (cm == 0).any():
        raise InputError("background.mtl", str(ov.scene.mtl.path), f"{int((cm == 0).sum())} "
                         "pixels have no class (masked with no valid neighbour)",
                         "Crop the scene to its valid part (background.bounds / --bounds)")
    feats = ov.features
    refl = {b: feats[..., k] for k, b in enumerate((2, 3, 4, 5, 6, 7))}
    albedo = broadband_albedo(refl).astype(np.float32)
    level = ov.scene.level
    notes = list(ov.notes)
    src = ("Landsat surface reflectance (Liang 2001 broadband)" if level == "L2" else
           "Landsat top-of-atmosphere reflectance (Liang 2001 broadband; no atmospheric "
           "correction: approximate)")
    albedo[cm == WATER] = np.nan
    if elevation is None:
        elev = np.zeros(grid.shape, np.float32)
        slope = np.zeros(grid.shape, np.float32)
        aspect = np.zeros(grid.shape, np.float32)
        notes.append("no DEM: the ground is taken as level (no slope or aspect in the sun)")
    else:
        elev = np.asarray(elevation, dtype=float)
        elev = np.where(np.isfinite(elev), elev, 0.0)
        slope, aspect = slope_aspect(elev, grid.resolution)
        elev = elev.astype(np.float32)
        if dem_note:
            notes.append(dem_note)
    when = pd.Timestamp(ov.scene.mtl.acquired_utc)
    when = when.tz_localize("UTC") if when.tzinfo is None else when.tz_convert("UTC")
    sat = str(ov.scene.mtl.spacecraft).replace("_", "-").title() if hasattr(
        ov.scene.mtl, "spacecraft") else "Landsat"
    obs = Observation(lst=np.asarray(ov.lst, dtype=np.float32), time_utc=when,
                      source=f"{sat} {level} {ov.lst_source}, {when:%Y-%m-%d %H:%M} UTC",
                      accuracy_K=float(ov.lst_accuracy_k))
    return GroundCover(grid=grid, class_map=cm.astype(np.uint8), elevation=elev,
                       slope_deg=np.asarray(slope, np.float32),
                       aspect_deg=np.asarray(aspect, np.float32), albedo=albedo,
                       albedo_source=src, origin="scene",
                       label=f"real scene: {obs.source}", observation=obs, notes=tuple(notes))


# ---------------------------------------------------------------------------------------
# Orientation groups
# ---------------------------------------------------------------------------------------
def orientation_bins(slope_deg, aspect_deg):
    """Group pixels by orientation.

    Returns
    -------
    index : ndarray int (rows, cols)
        Bin of each pixel (0: level ground, slope below ``SLOPE_EDGES_DEG[1]``).
    slope, aspect : ndarray (n_bins,)
        Mean slope [deg] and circular-mean aspect [deg] of the pixels of each bin (level
        ground: 0, 180).
    """
    s = np.nan_to_num(np.asarray(slope_deg, dtype=float))
    a = np.mod(np.nan_to_num(np.asarray(aspect_deg, dtype=float)), 360.0)   # level: no aspect
    sb = np.clip(np.searchsorted(SLOPE_EDGES_DEG, s, side="right") - 1, 0,
                 len(SLOPE_EDGES_DEG) - 2)
    width = 360.0 / ASPECT_SECTORS
    sector = np.floor(np.mod(a + 0.5 * width, 360.0) / width).astype(int) % ASPECT_SECTORS
    raw = np.where(sb == 0, 0, 1 + (sb - 1) * ASPECT_SECTORS + sector)
    used, index = np.unique(raw, return_inverse=True)
    index = index.reshape(s.shape)
    n = used.size
    counts = np.bincount(index.ravel(), minlength=n)
    slope = np.bincount(index.ravel(), s.ravel(), minlength=n) / counts
    sx = np.bincount(index.ravel(), np.sin(np.radians(a)).ravel(), minlength=n)
    cx = np.bincount(index.ravel(), np.cos(np.radians(a)).ravel(), minlength=n)
    aspect = np.mod(np.degrees(np.arctan2(sx, cx)), 360.0)
    level = used == 0
    slope[level] = 0.0
    aspect[level] = 180.0
    return index, slope, aspect


# ---------------------------------------------------------------------------------------
# The background
# ---------------------------------------------------------------------------------------
@dataclass(frozen=True)
class ClassFit:
    """Anchoring of one class on the scene: the fitted parameter's spread and what the fit
    could not reach (the residual, LST minus the model at the overpass)."""

    name: str
    pixels: int
    parameter: str
    unit: str
    median: float
    p05: float
    p95: float
    albedo_reflectance_median: float
    at_bound_fraction: float
    residual_median_K: float
    residual_p05_K: float
    residual_p95_K: float
    residual_rms_K: float


@dataclass(eq=False)
class PhysicalBackground:
    """The port background of one run: temperatures of every pixel at any time.

    Attributes
    ----------
    ground : GroundCover
    times_s : ndarray (n_t,)
        Times of the column solution [s after local midnight of the run's first day].
    period_s : float or None
        One day for a periodic (design-day) run; None for a weather record.
    column_temperature : ndarray float32 (n_t, n_columns)
        Surface temperature of every solved column [K].
    land : ndarray int64
        Flat indices of the land pixels.
    corners : ndarray int32 (n_land, 4)
        The four columns each land pixel interpolates between (albedo x wetness).
    weights : ndarray float32 (n_land, 4)
        Their bilinear weights [-].
    residual : ndarray float32
        Anchoring residual per land pixel [K] (zeros without a scene).
    residual_weight : ndarray (n_t,)
        Factor of the residual at each solved time (:data:`RESIDUAL_MODES`).
    water : ndarray int64
        Flat indices of the water pixels.
    water_temperature : ndarray (n_t,)
        The sea's skin temperature [K] (the ship's sea).
    water_anomaly : ndarray float32
        Fixed pattern of the water pixels [K] (zeros without a scene).
    sea_bulk : ndarray (n_t,)
        The weather's bulk sea temperature [K].
    albedo : ndarray float32 (rows, cols)
        Albedo of every land pixel as used (fitted with a scene) [-]; NaN on water.
    fitted : ndarray float32 (n_land,)
        The anchored parameter of every land pixel (albedo [-] or surface resistance
        [s m-1], by class: :attr:`fits`); NaN without a scene.
    fits : list of ClassFit
    utc_offset_hours : float
    start : pandas.Timestamp
        Local midnight of the first day (the clock's zero).
    label : str
    notes : list of str
    timings : dict
    """

    ground: GroundCover
    times_s: np.ndarray
    period_s: float | None
    column_temperature: np.ndarray
    land: np.ndarray
    corners: np.ndarray
    weights: np.ndarray
    residual: np.ndarray
    residual_weight: np.ndarray
    water: np.ndarray
    water_temperature: np.ndarray
    water_anomaly: np.ndarray
    sea_bulk: np.ndarray
    albedo: np.ndarray
    fits: list
    utc_offset_hours: float
    start: pd.Timestamp
    residual_mode: str = RESIDUAL_MODES[0]
    column_info: pd.DataFrame | None = field(default=None, repr=False)
    fitted: np.ndarray | None = field(default=None, repr=False)
    label: str = ""
    notes: list = field(default_factory=list)
    timings: dict = field(default_factory=dict)
    outputs: dict = field(default_factory=dict)

    # -- the protocol of the imaging stage (imaging.scene.as_scene_background) ----------
    @property
    def grid(self) -> SceneGrid:
        return self.ground.grid

    @property
    def class_map(self) -> np.ndarray:
        return self.ground.class_map

    @property
    def synthetic(self) -> bool:
        return self.ground.origin == "synthetic"

    def _locate(self, seconds: float):
        t = self.times_s
        s = float(seconds)
        require(math.isfinite(s), "time", seconds, "must be finite")
        if self.period_s is not None:
            s = t[0] + (s - t[0]) % self.period_s
            if s > t[-1]:                     # between the last sample and the next day's first
                w = (s - t[-1]) / (t[0] + self.period_s - t[-1])
                return len(t) - 1, 0, w
        elif not (t[0] - 1e-6 <= s <= t[-1] + 1e-6):
            raise InputError("time", f"{s / HOUR:.3f} h", f"must lie within the simulated span "
                             f"[{t[0] / HOUR:g}, {t[-1] / HOUR:g}] h of the weather record")
        k = int(np.clip(np.searchsorted(t, s, side="right") - 1, 0, len(t) - 2))
        w = (s - t[k]) / (t[k + 1] - t[k])
        return k, k + 1, float(np.clip(w, 0.0, 1.0))

    def temperature_at(self, hour: float) -> np.ndarray:
        """Surface temperature of every pixel [K], float32 (rows, cols), at ``hour`` hours
        after local midnight of the first day (periodic runs fold it into the day)."""
        k0, k1, w = self._locate(float(hour) * HOUR)
        col = ((1.0 - w) * self.column_temperature[k0].astype(float)
               + w * self.column_temperature[k1].astype(float))
        rw = (1.0 - w) * self.residual_weight[k0] + w * self.residual_weight[k1]
        out = np.empty(self.class_map.size, np.float32)
        _land_frame(col, self.corners, self.weights, self.residual, float(rw), self.land, out)
        tw = (1.0 - w) * self.water_temperature[k0] + w * self.water_temperature[k1]
        out[self.water] = tw + self.water_anomaly
        return out.reshape(self.class_map.shape)

    def sea_temperature_at(self, hour: float) -> float:
        """The sea's skin temperature [K] (the temperature of water without anomaly)."""
        k0, k1, w = self._locate(float(hour) * HOUR)
        return float((1.0 - w) * self.water_temperature[k0] + w * self.water_temperature[k1])

    @property
    def hours_local(self) -> np.ndarray:
        """Whole hours of the first day [h] (the layers of :attr:`temperature`)."""
        return np.arange(24.0)

    @property
    def temperature(self) -> np.ndarray:
        """Hourly layers of the first day [K], float32 (24, rows, cols)."""
        return np.stack([self.temperature_at(h) for h in self.hours_local])

    def summary(self) -> dict:
        """JSON-able key figures."""
        g = self.ground
        counts = {CLASS_NAMES[int(c)]: int(n) for c, n in zip(*np.unique(g.class_map,
                                                                          return_counts=True))}
        out = {
            "model": "physical (surface energy balance per pixel, shipthermal environment)",
            "background": g.label, "origin": g.origin, "synthetic": self.synthetic,
            "shape": list(g.grid.shape), "crs": str(g.grid.crs),
            "start_local": str(self.start), "utc_offset_hours": self.utc_offset_hours,
            "span_h": [float(self.times_s[0] / HOUR), float(self.times_s[-1] / HOUR)],
            "periodic": self.period_s is not None, "columns": int(self.column_temperature.shape[1]),
            "class_pixels": counts, "albedo_source": g.albedo_source,
            "residual_mode": self.residual_mode,
            "sea_skin_minus_bulk_K": [float(np.min(self.water_temperature - self.sea_bulk)),
                                      float(np.max(self.water_temperature - self.sea_bulk))],
            "notes": list(g.notes) + list(self.notes),
            "timings_s": {k: round(v, 3) for k, v in self.timings.items()},
        }
        if g.observation is not None:
            out["anchored_on"] = g.observation.source
            out["lst_stated_accuracy_K"] = g.observation.accuracy_K
            out["fit_by_class"] = [f.__dict__ for f in self.fits]
        return out


@njit(parallel=True, cache=True)
def _land_frame(col, corners, weights, residual, rw, land, out):
    """``out[land[i]] = Σ_k weights[i, k] col[corners[i, k]] + rw residual[i]`` (one pass over
    the land pixels on the process's threads; :func:`_land_frame_reference` is the plain
    form the tests compare with)."""
    for i in prange(land.size):
        v = 0.0
        for k in range(4):
            v += weights[i, k] * col[corners[i, k]]
        out[land[i]] = v + rw * residual[i]


def _land_frame_reference(col, corners, weights, residual, rw, land, out):
    out[land] = (weights * col[corners]).sum(axis=1) + rw * residual


# ---------------------------------------------------------------------------------------
# Building it
# ---------------------------------------------------------------------------------------
def _scene_seconds(obs: Observation, start: pd.Timestamp, end_s: float, periodic: bool):
    """Seconds after ``start`` at which the scene is matched, and a note: the instant itself
    inside the simulated span, else its local clock time on the first day when the scene
    is within :data:`MAX_SCENE_DAYS` of the span."""
    when = obs.time_utc.tz_convert(start.tz)
    s = (when - start).total_seconds()
    if not periodic and 0.0 <= s <= end_s:
        return s, None
    span_end = start + pd.Timedelta(seconds=end_s)
    days = (start - when).total_seconds() / DAY if when < start else \
        (when - span_end).total_seconds() / DAY
    if days > MAX_SCENE_DAYS:
        raise InputError("background.mtl", f"scene of {when:%Y-%m-%d %H:%M %Z}",
                         f"must lie within {MAX_SCENE_DAYS:g} days of the simulated span "
                         f"({start:%Y-%m-%d} … {span_end:%Y-%m-%d}); it is {days:.0f} days away",
                         "Choose a scene closer to time.date, or move time.date to the scene's "
                         "date")
    clock = (when - when.normalize()).total_seconds()
    note = None if periodic else (f"the scene ({when:%Y-%m-%d %H:%M %Z}) lies outside the "
                                  "record: matched at its clock time on the first day")
    return clock, note


def _fit_position(t_ov, lst):
    """Where along a pixel's samples the model gives ``lst`` (piecewise-linear inverse of the
    surface temperature at the overpass over the samples of the fitted parameter).

    Parameters
    ----------
    t_ov : ndarray (n, K)
        Modelled temperature at the overpass at each sample [K] (falling with albedo and
        with wetness).
    lst : ndarray (n,)

    Returns
    -------
    position : ndarray (n,)
        Fractional sample index in [0, K - 1].
    residual : ndarray (n,)
        ``lst`` minus the model at that position [K] (non-zero only beyond the samples).
    """
    n, k = t_ov.shape
    pos = np.full(n, np.nan)
    # a night scene may be flat in the parameter: the nearest sample is taken where no
    # segment brackets the target
    for j in range(k - 1):
        a, b = t_ov[:, j], t_ov[:, j + 1]
        lo, hi = np.minimum(a, b), np.maximum(a, b)
        inside = np.isnan(pos) & (lst >= lo) & (lst <= hi)
        d = np.where(b != a, b - a, 1.0)
        pos = np.where(inside, j + np.clip((lst - a) / d, 0.0, 1.0), pos)
    rest = np.isnan(pos)
    if rest.any():
        pos[rest] = np.argmin(np.abs(t_ov[rest] - lst[rest, None]), axis=1)
    j0 = np.clip(np.floor(pos).astype(int), 0, k - 2)
    w = pos - j0
    rows = np.arange(n)
    model = (1.0 - w) * t_ov[rows, j0] + w * t_ov[rows, j0 + 1]
    return pos, lst - model


def _class_grid(cls):
    """The anchoring design of a class: ``(fit, albedos, conductances, default conductance)``.

    A class with a ``surface_resistance_range`` is fitted on its surface conductance
    ``g = 1/r_s`` [m s-1] (its wetness; the albedo is the pixel's own); a class without is
    fitted on its albedo within ``albedo_range``. A class without latent heat by default but
    with a range (paving that can be wet) starts dry (g = 0)."""
    if cls.surface_resistance_range is not None:
        r_lo, r_hi = cls.surface_resistance_range
        wet = 1.0 / r_lo
        dry = 1.0 / r_hi if cls.latent == "penman_monteith" and np.isfinite(r_hi) else 0.0
        default = 1.0 / cls.surface_resistance if cls.latent == "penman_monteith" else 0.0
        return ("surface_resistance", np.linspace(*cls.albedo_range, ALBEDO_SAMPLES_WET),
                np.linspace(dry, wet, CONDUCTANCE_SAMPLES), default)
    return ("albedo", np.linspace(*cls.albedo_range, ALBEDO_SAMPLES), np.array([-1.0]), -1.0)


def _positions(samples, values):
    """Fractional index of ``values`` in increasing ``samples`` (clipped to the ends)."""
    if samples.size == 1:
        return np.zeros(np.shape(values))
    return np.interp(values, samples, np.arange(samples.size, dtype=float))


def _corners(pos_a, pos_g, n_a, n_g, base):
    """The 4 columns and bilinear weights of pixels at fractional positions."""
    i0 = np.clip(np.floor(pos_a).astype(np.int64), 0, max(n_a - 2, 0))
    wa = np.clip(pos_a - i0, 0.0, 1.0) if n_a > 1 else np.zeros_like(pos_a)
    i1 = np.minimum(i0 + 1, n_a - 1)
    j0 = np.clip(np.floor(pos_g).astype(np.int64), 0, max(n_g - 2, 0))
    wg = np.clip(pos_g - j0, 0.0, 1.0) if n_g > 1 else np.zeros_like(pos_g)
    j1 = np.minimum(j0 + 1, n_g - 1)
    idx = np.stack([base + i0 * n_g + j0, base + i0 * n_g + j1, base + i1 * n_g + j0,
                    base + i1 * n_g + j1], axis=1)
    w = np.stack([(1 - wa) * (1 - wg), (1 - wa) * wg, wa * (1 - wg), wa * wg], axis=1)
    return idx, w


@dataclass(frozen=True, eq=False)
class _ColumnSet:
    """The columns of a scene: groups of (class, orientation) over its land pixels, each
    solved on its class's (albedo × conductance) grid (:func:`_class_grid`)."""

    names: dict              # class code -> name
    design: dict             # class code -> (fit, albedos, conductances, default conductance)
    g_of_pixel: np.ndarray   # group of every land pixel
    base: np.ndarray         # first column of every group
    slope: np.ndarray        # orientation bins' slope and aspect [deg]
    aspect: np.ndarray
    col_class: list          # SurfaceClass of every column
    col_albedo: np.ndarray   # [-]
    col_bin: np.ndarray      # orientation bin of every column
    resistance: np.ndarray   # surface resistance [s m-1] (-1: no latent heat)


def _column_set(ground: GroundCover, land, table) -> _ColumnSet:
    """Group the land pixels by class and orientation and lay out their columns."""
    flat = ground.class_map.ravel()
    names = {int(c): CLASS_NAMES[int(c)] for c in np.unique(flat[land])}
    for code, name in names.items():
        if name not in table:
            raise InputError(f"background.classes.{name}", None, "needs its surface properties "
                             f"(class {code} is in the scene)", f"Add [background.classes.{name}]"
                             f" (built-in classes: {', '.join(sorted(table))})")
    design = {c: _class_grid(table[n]) for c, n in names.items()}
    obin, slope, aspect = orientation_bins(ground.slope_deg, ground.aspect_deg)
    key = flat[land].astype(np.int64) * 1000 + obin.ravel()[land]
    groups, g_of_pixel = np.unique(key, return_inverse=True)
    g_class = (groups // 1000).astype(int)
    g_bin = (groups % 1000).astype(int)
    sizes = np.array([design[c][1].size * design[c][2].size for c in g_class])
    base = np.concatenate([[0], np.cumsum(sizes)[:-1]]).astype(np.int64)
    col_class, col_albedo, col_g, col_bin = [], [], [], []
    for g, c in enumerate(g_class):
        _, alb, cond, _ = design[c]
        aa, gg = np.meshgrid(alb, cond, indexing="ij")
        col_albedo.append(aa.ravel())
        col_g.append(gg.ravel())
        col_bin.append(np.full(aa.size, g_bin[g]))
        col_class += [table[names[c]]] * aa.size
    col_albedo, col_g, col_bin = (np.concatenate(x) for x in (col_albedo, col_g, col_bin))
    resistance = np.where(col_g > 0.0, 1.0 / np.where(col_g > 0.0, col_g, 1.0),
                          np.where(col_g == 0.0, DRY_RESISTANCE, -1.0))
    return _ColumnSet(names, design, g_of_pixel, base, slope, aspect, col_class, col_albedo,
                      col_bin, resistance)


def _column_forcing(cs: _ColumnSet, state, dtype=np.float64):
    """Absorbed short-wave and incoming long-wave of every column [W m-2], (n_t, n_columns)
    in ``dtype``: each orientation's plane-of-array sun, its sky view and the terrain at the
    air (float64 temporaries by blocks of rows, so a long record's float32 tables are never
    held twice)."""
    poa = _plane_of_array(state, cs.slope, cs.aspect, np.unique(cs.col_bin))
    svf = sky_view_factor(cs.slope)[cs.col_bin]
    n_t, n_c = poa.shape[0], cs.col_bin.size
    sw = np.empty((n_t, n_c), dtype)
    lw = np.empty((n_t, n_c), dtype)
    down, air = np.asarray(state.longwave_down), np.asarray(state.temp_air)
    for rows in _row_blocks(n_t, n_c):
        sw[rows] = (1.0 - cs.col_albedo)[None, :] * poa[rows][:, cs.col_bin]
        lw[rows] = longwave_incoming(down[rows, None], svf, air[rows, None])
    return sw, lw


def _fit_class(fit, alb, cond, pos_a, b, t_col, lst):
    """Fit one class's pixels at the overpass: the fitted parameter's positions on the
    class's grid, the residual [K] and the fitted values (albedo [-] or r_s [s m-1])."""
    n_a, n_g = alb.size, cond.size
    if fit == "albedo":
        prof = t_col[b[:, None] + np.arange(n_a)[None, :] * n_g]
        pos_a, r = _fit_position(prof, lst)
        return pos_a, None, r, np.interp(pos_a, np.arange(n_a), alb)
    i0 = np.clip(np.floor(pos_a).astype(np.int64), 0, n_a - 2)
    wa = (pos_a - i0)[:, None]
    j = np.arange(n_g)[None, :]
    prof = ((1 - wa) * t_col[b[:, None] + i0[:, None] * n_g + j]
            + wa * t_col[b[:, None] + (i0[:, None] + 1) * n_g + j])
    pos_g, r = _fit_position(prof, lst)
    gs = np.interp(pos_g, np.arange(n_g), cond)
    return pos_a, pos_g, r, np.where(gs > 0.0, 1.0 / np.where(gs > 0.0, gs, 1.0), np.inf)


def _class_fit(name, fit, values, r, at_bound, reflectance_albedo, residual) -> tuple:
    """The :class:`ClassFit` of one class and a warning when most of it is beyond reach."""
    # a dry pixel's surface resistance is infinite: order statistics, not interpolation
    q = np.sort(values)
    f = ClassFit(name=name, pixels=int(values.size), parameter=fit,
                 unit="-" if fit == "albedo" else "s m-1",
                 median=float(q[(q.size - 1) // 2]), p05=float(q[int(0.05 * (q.size - 1))]),
                 p95=float(q[int(np.ceil(0.95 * (q.size - 1)))]),
                 albedo_reflectance_median=float(np.median(reflectance_albedo)),
                 at_bound_fraction=float(at_bound.mean()),
                 residual_median_K=float(np.median(r)), residual_p05_K=float(np.percentile(r, 5)),
                 residual_p95_K=float(np.percentile(r, 95)),
                 residual_rms_K=float(np.sqrt(np.mean(r ** 2))))
    note = None
    if f.at_bound_fraction > 0.5 and abs(f.residual_median_K) > WATER_MISMATCH_K:
        note = (f"WARNING: {100 * f.at_bound_fraction:.0f} % of the {name} pixels are "
                f"{'colder' if f.residual_median_K < 0 else 'warmer'} at the overpass than the "
                f"model reaches at the end of its {fit.replace('_', ' ')} range (median "
                f"residual {f.residual_median_K:+.1f} K): the weather does not look like the "
                "scene's day (air temperature, wind, cloud), or the class table does not fit "
                f"this surface; the residual is carried as background.residual = '{residual}' "
                "says")
    return f, note


def _water_pattern(ground, water, obs, lst_all, model_w) -> tuple:
    """The water's fixed pattern [K] and the notes comparing the scene's water with the
    weather's sea skin at the overpass (``model_w``)."""
    if obs is None or not water.size:
        pattern = (np.zeros(water.size, np.float32) if ground.water_anomaly is None else
                   np.asarray(ground.water_anomaly, np.float32).ravel()[water])
        return pattern, []
    lst_w = lst_all[water]
    median_w = float(np.nanmedian(lst_w))
    diff = median_w - model_w
    notes = [f"scene water median {median_w:.2f} K against the weather's sea skin "
             f"{model_w:.2f} K at the overpass ({diff:+.2f} K); the water keeps its observed "
             "pattern around the weather's sea"]
    if abs(diff) > WATER_MISMATCH_K:
        notes.append(f"WARNING: the scene's water is {diff:+.1f} K from the weather's sea "
                     "temperature: check weather.temp_sea or the weather file's SST")
    return np.nan_to_num(lst_w - median_w).astype(np.float32), notes


def _at(series, times, s):
    """``series`` (n_t, ...) linearly at ``s`` [s]."""
    k0 = int(np.clip(np.searchsorted(times, s, side="right") - 1, 0, times.size - 2))
    wt = float(np.clip((s - times[k0]) / (times[k0 + 1] - times[k0]), 0.0, 1.0))
    return (1.0 - wt) * series[k0] + wt * series[k0 + 1]


def build_physical_background(ground: GroundCover, environment, *, end_s: float | None = None,
                              classes=None, residual: str = RESIDUAL_MODES[0],
                              step_s: float = COLUMN_STEP_S, progress: bool = False
                              ) -> PhysicalBackground:
    """Solve the background of ``ground`` under ``environment``.

    Parameters
    ----------
    ground : GroundCover
        :func:`ground_from_synthetic` or :func:`ground_from_overpass`.
    environment : shipthermal.environment.Environment
        The run's environment (the ship's): site, sun, weather, sea.
    end_s : float, optional
        End of a weather record's span [s after ``environment.start``] (required for a
        record; a periodic weather is one repeated day).
    classes : dict, optional
        Surface classes by name (:data:`.surface_classes.SURFACE_CLASSES` with the user's
        additions and overrides); default the built-in set.
    residual : {"solar", "constant", "none"}
        :data:`imaging.parameters.RESIDUAL_MODES` (default the first, ``solar``).
    step_s : float
        Column time step [s] (records longer than :data:`LONG_RECORD_DAYS`: forcing and
        results every :data:`LONG_RECORD_STEP_S`, in float32, solved in steps of
        ``step_s``).
    progress : bool
        Unused (the column solve takes about a second).

    Returns
    -------
    PhysicalBackground
    """
    t0 = _time.perf_counter()
    require(residual in RESIDUAL_MODES, "background.residual", residual,
            f"must be one of {', '.join(RESIDUAL_MODES)}")
    periodic = bool(environment.weather.periodic)
    if periodic:
        times = np.arange(0.0, DAY, step_s)
    substeps, dtype = 1, np.float64
    if not periodic:
        require(end_s is not None and end_s > 0, "end_s", end_s,
                "must give the record's span [s] for a weather record")
        if end_s > LONG_RECORD_DAYS * DAY and LONG_RECORD_STEP_S > step_s:
            substeps = int(round(LONG_RECORD_STEP_S / step_s))
            require(abs(substeps * step_s - LONG_RECORD_STEP_S) < 1e-6, "step_s", step_s,
                    f"must divide {LONG_RECORD_STEP_S:g} s for a record of more than "
                    f"{LONG_RECORD_DAYS:g} days")
            step_s, dtype = LONG_RECORD_STEP_S, np.float32
        times = np.arange(0.0, float(end_s) + 0.5 * step_s, step_s)
    table = SURFACE_CLASSES if classes is None else classes
    state = environment.at(times)
    timings = {"environment": _time.perf_counter() - t0}
    flat = ground.class_map.ravel()
    land = np.flatnonzero(flat != WATER)
    water = np.flatnonzero(flat == WATER)

    # 1. the columns and their forcing, 2. their solve
    t1 = _time.perf_counter()
    cs = _column_set(ground, land, table)
    sw, lw = _column_forcing(cs, state, dtype)
    timings["forcing"] = _time.perf_counter() - t1
    t1 = _time.perf_counter()
    temp, solve = _column_temperatures(cs.col_class, cs.resistance, sw, lw, state, environment,
                                       times, periodic, table, substeps)
    del sw, lw
    timings["columns"] = _time.perf_counter() - t1

    # 3. every land pixel on its class's grid: its own albedo, the class's wetness, or the
    #    values the scene's LST asks for
    t1 = _time.perf_counter()
    pixel_class = flat[land]
    albedo_px = np.full(land.size, np.nan)
    if ground.albedo is not None:
        albedo_px = np.asarray(ground.albedo, dtype=float).ravel()[land]
    default_a = np.zeros(land.size)
    for code, name in cs.names.items():
        default_a[pixel_class == code] = table[name].albedo
    albedo_px = np.where(np.isfinite(albedo_px), albedo_px, default_a)
    reflectance_albedo = albedo_px.copy()
    obs = ground.observation
    notes = []
    rweight = np.ones(times.size)
    skin = np.asarray(getattr(state, "temp_sea_skin", state.temp_sea), dtype=float)
    lst_all = t_col = None
    model_w = float("nan")
    if obs is not None:
        s_ov, note = _scene_seconds(obs, environment.start, float(times[-1]), periodic)
        notes += [note] if note else []
        t_col = _at(temp, times, s_ov)
        lst_all = np.asarray(obs.lst, dtype=float).ravel()
        model_w = float(_at(skin, times, s_ov))
        ghi_ov = float(_at(np.asarray(state.ghi), times, s_ov))
        if residual == "solar" and ghi_ov > 50.0:
            rweight = state.ghi / ghi_ov
        elif residual == "none":
            rweight = np.zeros(times.size)
    idx = np.zeros((land.size, 4), np.int64)
    wts = np.zeros((land.size, 4))
    res = np.zeros(land.size)
    fitted = np.full(land.size, np.nan)
    fits, outside = [], 0
    for code, name in cs.names.items():
        m = pixel_class == code
        fit, alb, cond, g_default = cs.design[code]
        outside += int(((albedo_px[m] < alb[0]) | (albedo_px[m] > alb[-1])).sum())
        pos_a = _positions(alb, albedo_px[m])
        pos_g = np.full(pos_a.size, float(_positions(cond, g_default)))
        b = cs.base[cs.g_of_pixel[m]]
        if obs is not None:
            pos_a, pg, res[m], fitted[m] = _fit_class(fit, alb, cond, pos_a, b, t_col,
                                                      lst_all[land[m]])
            pos = pos_a if pg is None else pg
            n = alb.size if pg is None else cond.size
            at_bound = ((pos <= 0.0) | (pos >= n - 1)) & (np.abs(res[m]) > 1e-6)
            pos_g = pos_g if pg is None else pg
            f, warn = _class_fit(name, fit, fitted[m], res[m], at_bound,
                                 reflectance_albedo[m], residual)
            fits.append(f)
            notes += [warn] if warn else []
        idx[m], wts[m] = _corners(pos_a, pos_g, alb.size, cond.size, b)
        if fit == "albedo":
            albedo_px[m] = np.interp(pos_a, np.arange(alb.size), alb)
    if outside and obs is None:
        notes.append(f"{outside} land pixels ({100 * outside / max(land.size, 1):.1f} %) have "
                     "an albedo outside their class's range: clipped to it")
    water_pattern, water_notes = _water_pattern(ground, water, obs, lst_all, model_w)
    notes += water_notes
    notes.append(f"{temp.shape[1]} columns ({len(cs.base)} class x orientation groups), spin-up "
                 f"{solve.spinup_days} days (last day-to-day change "
                 f"{float(np.max(solve.spinup_change)):.3g} K)")
    albedo_map = np.full(flat.size, np.nan, np.float32)
    albedo_map[land] = albedo_px
    info = pd.DataFrame({"class": [c.name for c in cs.col_class],
                         "slope_deg": cs.slope[cs.col_bin], "aspect_deg": cs.aspect[cs.col_bin],
                         "albedo": cs.col_albedo, "surface_resistance_s_m": cs.resistance})
    timings["pixels"] = _time.perf_counter() - t1
    timings["total"] = _time.perf_counter() - t0
    return PhysicalBackground(
        ground=ground, times_s=times, period_s=DAY if periodic else None,
        column_temperature=np.asarray(temp, np.float32), land=land, corners=idx.astype(np.int32),
        weights=wts.astype(np.float32), residual=res.astype(np.float32),
        residual_weight=np.asarray(rweight, dtype=float), water=water,
        water_temperature=skin, water_anomaly=water_pattern,
        sea_bulk=np.asarray(state.temp_sea, dtype=float),
        albedo=albedo_map.reshape(ground.class_map.shape), fits=fits,
        utc_offset_hours=environment.start.utcoffset().total_seconds() / HOUR,
        start=environment.start, residual_mode=residual, column_info=info,
        fitted=fitted.astype(np.float32), label=ground.label, notes=notes, timings=timings)


def _plane_of_array(state, slope, aspect, used_bins):
    """Global irradiance on each orientation bin's plane [W m-2], (n_t, n_bins): pvlib's
    plane-of-array irradiance (:func:`.surface_energy.shortwave_on_tilted`, isotropic sky
    diffuse, ground-reflected with :data:`GROUND_ALBEDO`); level ground takes the GHI."""
    out = np.zeros((state.ghi.size, slope.size))
    tilted = np.array([b for b in used_bins if slope[b] > 0.0], dtype=int)
    out[:, [b for b in used_bins if slope[b] == 0.0]] = np.asarray(state.ghi)[:, None]
    if tilted.size:
        poa = shortwave_on_tilted(slope[tilted], aspect[tilted], state.zenith, state.azimuth,
                                  state.dni, state.ghi, state.dhi, albedo_ground=GROUND_ALBEDO)
        out[:, tilted] = poa["poa_global"]
    return np.maximum(out, 0.0)


WIND_HEIGHT_M = 10.0
"""Height of the environment's wind [m] (weather files are reduced to 10 m on reading)."""

AIR_HEIGHT_M = 2.0
"""Height of the weather's air temperature and humidity [m]: screen height (WMO standard
1.25-2 m; EPW/TMY and buoy air temperatures are screen-level)."""

GROUND_ALBEDO = 0.2
"""Albedo of the terrain a tilted pixel sees (pvlib's default, a generic ground). ASSUMPTION."""


def land_convection(col_class, pressure=101325.0):
    """The land columns' convection, ``h(T_s, T_air, wind)`` [W m-2 K-1] for columns of the
    classes ``col_class``: the surface layer's log-law aerodynamic resistance between the
    10 m wind (:data:`WIND_HEIGHT_M`), the screen-level air (:data:`AIR_HEIGHT_M`) and each
    class's roughness lengths, with the bulk-Richardson stability factors
    (:func:`.surface_energy.convection_aerodynamic`)."""
    return convection_aerodynamic(np.array([c.roughness_length for c in col_class]),
                                  np.array([c.roughness_length_heat for c in col_class]),
                                  np.array([c.displacement_height for c in col_class]),
                                  height_wind=WIND_HEIGHT_M, height_temp=AIR_HEIGHT_M,
                                  stability=True, pressure=pressure)


def _column_temperatures(col_class, resistance, sw, lw, state, environment, times, periodic,
                         classes, substeps=1):
    """Surface temperature of every column [K], (n_t, n_columns), and the solve's report
    (:func:`.surface_energy.solve_surface_energy`).

    The deep ground below the diurnal wave and the rooms under the roofs are at the mean air
    temperature of the simulated span (ASSUMPTION: an unconditioned port warehouse; the deep
    ground of a periodic day in equilibrium with its air).

    Convection is the surface layer's: the log-law aerodynamic resistance between the 10 m
    wind and each class's roughness lengths, with the bulk-Richardson stability factors
    (:func:`.surface_energy.convection_aerodynamic`, FAO-56 eq. 4; Dyer 1974, Webb 1970). A
    30 m pixel in a port is part of a rough surface many pixels wide, not the leading edge of
    a flat plate: the ship's flat-plate correlation gives h ≈ 9 W m-2 K-1 at a July noon
    where EnergyPlus's DOE-2 gives ≈ 15 (tests/background, the EnergyPlus peer), and a
    sunlit surface 4-5 K hotter."""
    bottom = float(np.mean(state.temp_air))
    cols = dataclasses.replace(build_columns(col_class, bottom, classes=classes),
                               surface_resistance=np.asarray(resistance, dtype=float))
    pressure = 101325.0 * (1.0 - 2.25577e-5 * environment.altitude) ** 5.25588
    forcing = SurfaceForcing(time_step=float(times[1] - times[0]), shortwave_absorbed=sw,
                             longwave_down=lw, temp_air=np.asarray(state.temp_air, float),
                             relative_humidity=np.clip(state.relative_humidity, 0.0, 100.0),
                             wind_speed=np.asarray(state.wind_speed, float), pressure=pressure)
    res = solve_surface_energy(forcing, cols, convection=land_convection(col_class, pressure),
                               mode="periodic" if periodic else "record", substeps=substeps,
                               outputs=("temp_surface",), output_dtype=sw.dtype)
    return res.temp_surface, res


def _row_blocks(n_rows: int, n_cols: int, elements: int = 1 << 22):
    """Slices of rows of about ``elements`` values each."""
    step = max(1, elements // max(n_cols, 1))
    for start in range(0, n_rows, step):
        yield slice(start, min(n_rows, start + step))
