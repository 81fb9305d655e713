"""Anchoring on a scene: the scene's instant on the simulated span, the fit of each land
pixel's albedo or wetness to the scene's LST with what it cannot reach, and the water's
observed pattern around the weather's sea."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pandas as pd

from shipthermal.errors import InputError
from shipthermal.units import DAY

from .ground import Observation


WATER_MISMATCH_K = 2.0
"""A scene's median water this far from the weather's sea skin [K] is warned about:
beyond the stated accuracy of Landsat's surface temperature (about 1.5 K) and a day's
skin effects."""

MAX_SCENE_DAYS = 15.0
"""Largest distance [days] between a scene's acquisition and the simulated span for its
albedos and water pattern to stand for it. ASSUMPTION: vegetation, soil moisture and sea
surface patterns change over weeks; further apart, choose a closer scene."""

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
