"""What is known of a port's ground before any temperature: its classes, terrain and
albedo, from the synthetic port or a Landsat scene, and the scene to anchor on."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pandas as pd
from scipy.ndimage import gaussian_filter

from shipthermal.errors import InputError, require

from ..classify import CLASS_NAMES
from ..landsat.grid import SceneGrid
from ..synthetic import synthetic_surface
from ..terrain import slope_aspect


WATER = 1

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
