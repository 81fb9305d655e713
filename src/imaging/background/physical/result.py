"""The physical background of one run: temperatures of every pixel at any time from the
solved columns, the pixels' corners and the water's sea."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import pandas as pd
from numba import njit, prange

from shipthermal.errors import InputError, require
from shipthermal.units import HOUR, fold_time

from ...parameters import RESIDUAL_MODES
from ..classify import CLASS_NAMES
from ..landsat.grid import SceneGrid
from .ground import GroundCover


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
            s = fold_time(s, self.period_s, t[0])
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
