"""The ship's detectability calendar: what each overpass sees, and how it adds up by month.

For a thermal history over a weather record and a port background that follows the same
record, :func:`image_overpasses` renders the ship at every overpass (each with its own view
direction: :mod:`imaging.overpass`) and measures it as the paper does (local SCR, eq. 22;
signed contrast), with the apparent (brightness) temperatures of the ship and of its local
background; :func:`image_dense` renders every day at a fixed step for the day-of-year ×
local-time picture and the crossover times of every day. :func:`monthly_table` and
:func:`crossover_table` add them up by month; :func:`plot_calendar` draws the heatmap with
the overpasses marked and the monthly bars.

"Under the clutter" at an overpass means SCR below the threshold (default 1: the ship's mean
contrast to its local background is smaller than the background's own spread).
"""

from __future__ import annotations

import dataclasses
import os

import numpy as np
import pandas as pd

from shipthermal.atomic import atomic_path
from shipthermal.errors import check_range, require
from shipthermal.figures import OKABE_ITO
from shipthermal.optics.planck import brightness_temperature
from shipthermal.optics.responses import user_bands
from shipthermal.units import HOUR, utc_offset_text

from .experiment import render_series

__all__ = ["SCR_THRESHOLD", "image_overpasses", "image_dense", "monthly_table",
           "crossover_table", "crossover_dates_table", "plot_calendar", "overpass_seconds"]

SCR_THRESHOLD = 1.0
"""Default SCR below which an overpass counts as "under the clutter" [-] (eq. 22: the
contrast is smaller than the background's standard deviation)."""

_VIEW_ROUNDING_DEG = 0.05
"""Overpasses whose view directions round to the same 0.05 deg share one renderer (the
view rays are traced once per direction; 0.05 deg moves a pixel's footprint by < 1 m)."""


def overpass_seconds(overpasses, start: pd.Timestamp) -> np.ndarray:
    """Seconds after ``start`` (local midnight of the first day, tz-aware) of each
    overpass."""
    return np.array([(o.time_utc - start).total_seconds() for o in overpasses], dtype=float)


def image_overpasses(history, scenario, overpasses, start: pd.Timestamp, bands=("8-14",),
                     threshold: float = SCR_THRESHOLD, progress: bool = False) -> pd.DataFrame:
    """Render and measure the ship at every overpass.

    Parameters
    ----------
    history : imaging.thermal_history.ShipThermalHistory
        Over the record (times after ``start``).
    scenario : imaging.experiment.ImagingScenario
        The run's imaging (place, date = ``start``'s date, background, sky); its view
        direction is replaced by each overpass's.
    overpasses : list of imaging.overpass.Overpass
        Inside the history's span.
    start : pandas.Timestamp
        Local midnight of the first day (the clock's zero).
    bands : sequence of str
    threshold : float
        SCR under which an overpass is under the clutter [-].
    progress : bool

    Returns
    -------
    pandas.DataFrame
        One row per overpass and band: ``time_utc``, ``date_local``, ``time_local``,
        ``hours`` [h after ``start``], ``satellite``, ``view_zenith_deg``,
        ``view_azimuth_deg``, ``band``, ``scr`` [-], ``contrast`` [W m-2 sr-1],
        ``ship_apparent_K``, ``background_apparent_K``, ``apparent_contrast_K`` (brightness
        temperatures of the at-aperture radiance), ``std_background`` [W m-2 sr-1],
        ``sun_zenith_deg``, ``daytime``, ``under_clutter``, ``atmosphere_model`` (the
        model atmosphere the overpass was seen through:
        :meth:`imaging.experiment.ImagingScenario.atmosphere_model_at`).
    """
    check_range("calendar.threshold", threshold, 0.0, 1.0e3, low_open=True)
    if not overpasses:
        return pd.DataFrame(columns=["time_utc", "band", "scr"])
    secs = overpass_seconds(overpasses, start)
    rows = []
    groups: dict = {}
    for o, s in zip(overpasses, secs):
        key = (round(o.view_zenith_deg / _VIEW_ROUNDING_DEG) * _VIEW_ROUNDING_DEG,
               round(o.view_azimuth_deg / _VIEW_ROUNDING_DEG) * _VIEW_ROUNDING_DEG)
        groups.setdefault(key, []).append((s, o))
    for (zen, azi), members in groups.items():
        members.sort(key=lambda m: m[0])
        scen = dataclasses.replace(scenario, view_zenith_deg=float(zen),
                                   view_azimuth_deg=float(azi) if zen > 0.0 else 0.0)
        t = np.array([m[0] for m in members])
        keep = np.concatenate([[True], np.diff(t) > 1e-6])       # one frame per instant
        res = render_series(history, scen, tuple(bands), t[keep], crop_px=32,
                            progress=progress, stack_step_s=1e12)
        for band, sr in res.items():
            m = sr.metrics.set_index("time_s")
            for s, o in members:
                r = m.loc[s]
                with user_bands(scenario.user_bands):       # a user sensor's band
                    ship = float(brightness_temperature(r["mean_target"], band))
                    back = float(brightness_temperature(r["mean_background"], band))
                local = o.time_utc.tz_convert(start.tz)
                rows.append(dict(
                    time_utc=o.time_utc, date_local=str(local.date()),
                    time_local=f"{local:%H:%M}", hours=s / HOUR, satellite=o.satellite,
                    view_zenith_deg=o.view_zenith_deg, view_azimuth_deg=o.view_azimuth_deg,
                    band=band, scr=float(r["scr"]), contrast=float(r["contrast"]),
                    ship_apparent_K=ship, background_apparent_K=back,
                    apparent_contrast_K=ship - back, std_background=float(r["std_background"]),
                    sun_zenith_deg=float(r["sun_zenith_deg"]),
                    daytime=bool(r["sun_zenith_deg"] < 90.0),
                    under_clutter=bool(r["scr"] < threshold),
                    atmosphere_model=scen.atmosphere_model_at(s)))
    return pd.DataFrame(rows).sort_values(["time_utc", "band"]).reset_index(drop=True)


def image_dense(history, scenario, span_s: float, step_s: float, bands=("8-14",),
                progress: bool = False) -> dict:
    """Every day of the record at a fixed step (the scenario's own view): ``{band:
    SeriesResult}`` (metrics and the crossovers of the whole span)."""
    check_range("calendar.dense_step", step_s, 60.0, 6.0 * HOUR, "s")
    t = np.arange(0.0, float(span_s) + 1.0, float(step_s))
    return render_series(history, scenario, tuple(bands), t, crop_px=32, progress=progress,
                         stack_step_s=1e12)


def _month(ts) -> str:
    return f"{ts:%Y-%m}"


def monthly_table(overpass_df: pd.DataFrame, threshold: float = SCR_THRESHOLD) -> pd.DataFrame:
    """Per month and band: overpasses, how many under the clutter and their fraction (all,
    by day, by night), the median SCR and the median apparent contrast [K]."""
    if overpass_df.empty:
        return pd.DataFrame(columns=["month", "band", "overpasses", "under_clutter",
                                     "fraction_under"])
    df = overpass_df.assign(month=overpass_df["date_local"].str.slice(0, 7))
    rows = []
    for (month, band), g in df.groupby(["month", "band"], sort=True):
        day, night = g[g["daytime"]], g[~g["daytime"]]
        rows.append(dict(
            month=month, band=band, overpasses=len(g), under_clutter=int(g["under_clutter"].sum()),
            fraction_under=float(g["under_clutter"].mean()),
            day_overpasses=len(day),
            fraction_under_day=float(day["under_clutter"].mean()) if len(day) else np.nan,
            night_overpasses=len(night),
            fraction_under_night=float(night["under_clutter"].mean()) if len(night) else np.nan,
            scr_median=float(g["scr"].median()),
            apparent_contrast_median_K=float(g["apparent_contrast_K"].median()),
            threshold=threshold))
    return pd.DataFrame(rows)


def crossover_table(dense: dict, start: pd.Timestamp) -> tuple:
    """The crossovers of the dense series: every one (``band, date_local, time_local,
    hours, direction``) and per month and direction the median and 5-95 % range of the local
    clock time [h]."""
    rows = []
    for band, sr in dense.items():
        for c in sr.crossovers:
            local = start + pd.Timedelta(seconds=float(c.time))
            rows.append(dict(band=band, date_local=str(local.date()),
                             time_local=f"{local:%H:%M}",
                             clock_h=local.hour + local.minute / 60.0 + local.second / 3600.0,
                             hours=c.time / HOUR, direction=c.direction))
    every = pd.DataFrame(rows, columns=["band", "date_local", "time_local", "clock_h", "hours",
                                        "direction"])
    stats = []
    if len(every):
        for (month, band, direction), g in every.assign(
                month=every["date_local"].str.slice(0, 7)).groupby(["month", "band",
                                                                     "direction"]):
            q = np.percentile(g["clock_h"], [5, 50, 95])
            stats.append(dict(month=month, band=band, direction=direction, crossovers=len(g),
                              days=g["date_local"].nunique(), median_clock_h=q[1],
                              p05_clock_h=q[0], p95_clock_h=q[2]))
    return every, pd.DataFrame(stats, columns=["month", "band", "direction", "crossovers",
                                               "days", "median_clock_h", "p05_clock_h",
                                               "p95_clock_h"])


def crossover_dates_table(every: pd.DataFrame) -> pd.DataFrame:
    """The crossovers of several years on the same calendar dates: per date (``MM-DD``),
    band and direction, the years with such a crossover that day, the crossovers, and the
    median and 5-95 % range of the local clock time [h] over all of them (``every``: the
    rows of :func:`crossover_table` with a ``year`` column)."""
    cols = ["date", "band", "direction", "years", "crossovers", "median_clock_h",
            "p05_clock_h", "p95_clock_h", "first_year", "last_year"]
    if not len(every):
        return pd.DataFrame(columns=cols)
    rows = []
    for (date, band, direction), g in every.assign(
            date=every["date_local"].str.slice(5)).groupby(["date", "band", "direction"]):
        q = np.percentile(g["clock_h"], [5, 50, 95])
        rows.append(dict(date=date, band=band, direction=direction,
                         years=g["year"].nunique(), crossovers=len(g), median_clock_h=q[1],
                         p05_clock_h=q[0], p95_clock_h=q[2], first_year=int(g["year"].min()),
                         last_year=int(g["year"].max())))
    return pd.DataFrame(rows, columns=cols)


def plot_calendar(path, dense: dict, overpass_df: pd.DataFrame, monthly: pd.DataFrame,
                  start: pd.Timestamp, band: str, threshold: float = SCR_THRESHOLD,
                  label: str = "") -> str:
    """Day × local-time map of log10 SCR (dense frames) with the overpasses marked (filled
    orange: under the clutter; black ring: seen), and the monthly fraction of overpasses
    under the clutter (bars from zero). PNG, written atomically."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.colors import TwoSlopeNorm

    require(band in dense, "band", band, f"must be one of {sorted(dense)}")
    m = dense[band].metrics
    hours = m["time_h"].to_numpy()
    days = int(np.floor(hours.max() / 24.0 - 1e-9)) + 1
    step_h = float(np.median(np.diff(hours))) if hours.size > 1 else 1.0
    per_day = int(round(24.0 / step_h))
    grid = np.full((per_day, days), np.nan)
    for h, v in zip(hours, m["scr"].to_numpy()):
        d = int(h // 24.0)
        k = int(round((h - 24.0 * d) / step_h))
        if d < days and k < per_day:
            grid[k, d] = np.log10(max(v, 1e-3))
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(11, 4.2), width_ratios=(3, 1),
                                 constrained_layout=True)
    lo = np.nanmin(grid) if np.isfinite(grid).any() else -1.0
    hi = np.nanmax(grid) if np.isfinite(grid).any() else 1.0
    norm = TwoSlopeNorm(vcenter=np.log10(threshold), vmin=min(lo, np.log10(threshold) - 0.1),
                        vmax=max(hi, np.log10(threshold) + 0.1))
    im = ax.imshow(grid, origin="lower", aspect="auto", cmap="RdBu", norm=norm,
                   extent=[0, days, 0, 24])
    cb = fig.colorbar(im, ax=ax, shrink=0.9)
    cb.set_label(f"log$_{{10}}$ local SCR (SCR = {threshold:g} at the white centre)")
    op = overpass_df[overpass_df["band"] == band]
    if len(op):
        x = op["hours"].to_numpy() / 24.0
        clock = np.mod(op["hours"].to_numpy(), 24.0)
        under = op["under_clutter"].to_numpy()
        # filled orange under the clutter, open rings where the ship is seen: told apart on
        # the colour map's white centre and its dark ends alike
        ax.scatter(np.floor(x[under]) + 0.5, clock[under], s=34, c=OKABE_ITO["orange"],
                   edgecolors="k", linewidths=0.8, label=f"overpass, SCR < {threshold:g}",
                   zorder=3)
        ax.scatter(np.floor(x[~under]) + 0.5, clock[~under], s=28, facecolors="none",
                   edgecolors="k", linewidths=1.0, label="overpass, ship seen", zorder=3)
        ax.legend(loc="upper right", fontsize=7, framealpha=0.8)
    ticks = np.arange(0, days + 1, max(1, days // 8))
    ax.set_xticks(ticks)
    ax.set_xticklabels([f"{start + pd.Timedelta(days=int(d)):%b %d}" for d in ticks],
                       fontsize=8)
    ax.set_yticks(range(0, 25, 3))
    ax.set_ylabel(f"local time [h] ({utc_offset_text(start.utcoffset().total_seconds() / HOUR)})")
    ax.set_title(f"Local SCR of the ship, {band} µm, every {step_h * 60:.0f} min"
                 + (f"\n{label}" if label else ""), fontsize=9)
    mb = monthly[monthly["band"] == band] if len(monthly) else monthly
    if len(mb):
        bx.bar(mb["month"], mb["fraction_under"], color=OKABE_ITO["blue"])
        for i, (n, k, f) in enumerate(zip(mb["overpasses"], mb["under_clutter"],
                                          mb["fraction_under"])):
            bx.text(i, f + 0.02, f"{k}/{n}", ha="center", va="bottom", fontsize=7,
                    color="black", rotation=90 if len(mb) > 6 else 0)   # a year: upright
    bx.set_ylim(0.0, 1.0)
    bx.set_ylabel(f"overpasses with SCR < {threshold:g}")
    bx.set_title("by month", fontsize=9)
    bx.tick_params(axis="x", labelrotation=45, labelsize=8)
    with atomic_path(path) as tmp:
        fig.savefig(tmp, format="png", dpi=120)
        plt.close(fig)
    return os.fspath(path)
