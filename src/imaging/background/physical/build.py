"""Building the physical background: the solved instants, the columns under the run's
environment, every land pixel placed among its group's columns (anchored on the scene when
there is one), the water's sea."""

from __future__ import annotations

import time as _time

import numpy as np
import pandas as pd

from shipthermal.errors import require
from shipthermal.units import DAY, HOUR

from ...parameters import RESIDUAL_MODES
from ..surface_classes import SURFACE_CLASSES
from .anchoring import _at, _class_fit, _fit_class, _scene_seconds, _water_pattern
from .columns import _column_forcing, _column_set, _column_temperatures, _corners, _positions
from .ground import WATER, GroundCover
from .result import PhysicalBackground

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



def _time_grid(periodic: bool, end_s: float | None, step_s: float) -> tuple:
    """The solved instants [s after local midnight], the solver's substeps per instant and
    the tables' dtype: a day every ``step_s`` for a periodic weather, the record's span for a
    record (every :data:`LONG_RECORD_STEP_S` in float32 beyond :data:`LONG_RECORD_DAYS`)."""
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
    return times, substeps, dtype


def _pixel_albedos(ground: GroundCover, land, pixel_class, names: dict, table) -> np.ndarray:
    """Every land pixel's own albedo [-], its class's where the ground has none."""
    albedo_px = np.full(land.size, np.nan)
    if ground.albedo is not None:
        albedo_px = np.asarray(ground.albedo, dtype=float).ravel()[land]
    default_a = np.zeros(land.size)
    for code, name in names.items():
        default_a[pixel_class == code] = table[name].albedo
    return np.where(np.isfinite(albedo_px), albedo_px, default_a)


def _scene_on_columns(obs, environment, state, times, temp, skin, periodic: bool,
                      residual: str) -> tuple:
    """The scene's instant on the solved span: the columns' temperature there, the scene's
    LST, the weather's sea skin there, the residual's weight at every solved time and the
    note on where the scene was matched. Without a scene: no columns, no LST, NaN sea, unit
    weights."""
    notes = []
    rweight = np.ones(times.size)
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
    return t_col, lst_all, model_w, rweight, notes


def _place_pixels(cs, land, pixel_class, albedo_px, obs, t_col, lst_all, residual: str) -> dict:
    """Every land pixel on its class's grid: its own albedo, the class's wetness, or the
    values the scene's LST asks for (fitted per class). Returns the pixels' four corner
    columns and weights, residuals [K], fitted values, albedos as used, the classes' fits,
    the notes and how many albedos fell outside their class's range."""
    reflectance_albedo = albedo_px
    albedo_px = albedo_px.copy()
    notes = []
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
    return {"corners": idx, "weights": wts, "residual": res, "fitted": fitted,
            "albedo": albedo_px, "fits": fits, "notes": notes, "outside": outside}


def _column_info(cs) -> pd.DataFrame:
    """One row per solved column: class, orientation, albedo and surface resistance."""
    return pd.DataFrame({"class": [c.name for c in cs.col_class],
                         "slope_deg": cs.slope[cs.col_bin], "aspect_deg": cs.aspect[cs.col_bin],
                         "albedo": cs.col_albedo, "surface_resistance_s_m": cs.resistance})


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
    times, substeps, dtype = _time_grid(periodic, end_s, step_s)
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

    # 3. every land pixel on its class's grid, 4. the water's sea
    t1 = _time.perf_counter()
    pixel_class = flat[land]
    albedo_px = _pixel_albedos(ground, land, pixel_class, cs.names, table)
    obs = ground.observation
    skin = np.asarray(getattr(state, "temp_sea_skin", state.temp_sea), dtype=float)
    t_col, lst_all, model_w, rweight, notes = _scene_on_columns(
        obs, environment, state, times, temp, skin, periodic, residual)
    px = _place_pixels(cs, land, pixel_class, albedo_px, obs, t_col, lst_all, residual)
    notes += px["notes"]
    outside = px["outside"]
    if outside and obs is None:
        notes.append(f"{outside} land pixels ({100 * outside / max(land.size, 1):.1f} %) have "
                     "an albedo outside their class's range: clipped to it")
    water_pattern, water_notes = _water_pattern(ground, water, obs, lst_all, model_w)
    notes += water_notes
    notes.append(f"{temp.shape[1]} columns ({len(cs.base)} class x orientation groups), spin-up "
                 f"{solve.spinup_days} days (last day-to-day change "
                 f"{float(np.max(solve.spinup_change)):.3g} K)")
    albedo_map = np.full(flat.size, np.nan, np.float32)
    albedo_map[land] = px["albedo"]
    info = _column_info(cs)
    timings["pixels"] = _time.perf_counter() - t1
    timings["total"] = _time.perf_counter() - t0
    return PhysicalBackground(
        ground=ground, times_s=times, period_s=DAY if periodic else None,
        column_temperature=np.asarray(temp, np.float32), land=land,
        corners=px["corners"].astype(np.int32), weights=px["weights"].astype(np.float32),
        residual=px["residual"].astype(np.float32),
        residual_weight=np.asarray(rweight, dtype=float), water=water,
        water_temperature=skin, water_anomaly=water_pattern,
        sea_bulk=np.asarray(state.temp_sea, dtype=float),
        albedo=albedo_map.reshape(ground.class_map.shape), fits=px["fits"],
        utc_offset_hours=environment.start.utcoffset().total_seconds() / HOUR,
        start=environment.start, residual_mode=residual, column_info=info,
        fitted=px["fitted"].astype(np.float32), label=ground.label, notes=notes,
        timings=timings)
