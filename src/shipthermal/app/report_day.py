"""The day as it unfolds, for the HTML report: a first screen and a time slider.

Built from the files of a run directory only:

* ``imaging/metrics_<season>_<band>.csv`` — SCR and contrast over the day;
* ``imaging/images_<season>_<band>.nc`` — the at-aperture radiance stack around the ship;
* ``imaging/summary.json`` — the place, date and zone of each season, what the background is;
* ``thermal/<case>/history.npz`` — the ship's outer-surface temperature over the day
  (``history.h5`` for a weather record: its first day is shown);
* ``ensemble/crossovers.csv`` — a weather ensemble's crossover times, when the run has one.

The first screen answers *when is the ship hardest to see, in which band, and how sure is
that*: the time of the lowest local SCR (paper eq. 22) per season and band on the local
clock named with its UTC offset, the periods in which the SCR is below
:data:`SCR_CLUTTER_LIMIT` (the target-background contrast is smaller than the background's
own standard deviation), and what the answer rests on: the frame interval, the physical
uncertainty (a weather ensemble's median and 5–95 % range when there is one, else how far
an error of :data:`SENSITIVITY_K` in the ship's temperature moves each crossover), the frames
where the SCR spikes only because the background's spread collapses, the margin to the
other band, where the ship temperatures come from and what the background is.

The slider section holds one frame per hour and one at each key moment (the lowest SCR and
every crossover of the first day, with buttons that jump there) for every season and band
(one colour scale per band and season) and for the ship's surface temperature (one scale
per case), and one SCR chart per season with both bands on a log scale, SCR = 1 marked and
a cursor at the chosen time. Everything is embedded (PNG ``data:`` URIs, inline SVG, one
small inline script); no external URL.
"""

from __future__ import annotations

import base64
import html
import io
import json
from pathlib import Path

import numpy as np
import pandas as pd

from imaging.metrics import background_window
from imaging.parameters import SENSOR_BANDS
from shipthermal.optics.planck import brightness_temperature

from ..figures import BAND_STYLES, OKABE_ITO, band_label, polygon_index_raster, unit_label
from ..geometry.surface_maps import surface_frame_figure
from ..units import latitude_text, longitude_text, strip_units, zone_text
from .pipeline import history_file, load_history

__all__ = ["SCR_CLUTTER_LIMIT", "SLIDER_HOURS", "SPREAD_COLLAPSE", "SPREAD_WINDOW_H",
           "SENSITIVITY_K",
           "hardest_to_see", "first_screen", "day_section", "slider_hours", "SCRIPT"]

#: SCR below which the ship's mean contrast to its local background is smaller than the
#: background's standard deviation (eq. 22: SCR = |contrast| / std_background) [-].
SCR_CLUTTER_LIMIT = 1.0

#: Hours of the slider [h after local midnight]; key moments are added between them.
SLIDER_HOURS = tuple(range(25))

#: A frame's background spread has collapsed when its standard deviation is below this
#: fraction of the median over the surrounding :data:`SPREAD_WINDOW_H` [-]: the SCR then
#: spikes because the background is momentarily uniform (e.g. water and quay passing
#: through the same radiance), not because the ship stands out more. ASSUMPTION: half; a
#: running median follows the slow day-night swing of the spread, so only brief dips count.
SPREAD_COLLAPSE = 0.5

#: Width of the running median that a frame's background spread is compared with [h]
SPREAD_WINDOW_H = 2.0

#: Error of the ship's temperature relative to its background for the quick sensitivity of
#: the crossover times [K] (the report states times per kelvin)
SENSITIVITY_K = 1.0

#: Side of the image crop shown around the ship [pixels] and its enlargement factor [-].
_CROP_PX = 40
_ZOOM = 5

#: Percentiles of the shared colour scale of the image frames (as the panel figures) [%].
_CLIM_PERCENTILES = (1.0, 99.5)

_R_UNIT = unit_label("W m-2 sr-1")


def _b64png(png: bytes) -> str:
    return "data:image/png;base64," + base64.b64encode(png).decode("ascii")


def _hhmm(hours: float) -> str:
    m = int(round(hours * 60.0))
    return f"{(m // 60) % 24:02d}:{m % 60:02d}" if m < 1440 else "24:00"


def split_series_name(name: str) -> tuple[str, str]:
    """``(season, band)`` of a series file's ``<season>_<band>``: both may hold underscores
    (``subarctic_summer``, ``landsat8_tirs_b10``), so the band is matched against the named
    bands first (longest first), else taken after the last underscore."""
    for band in sorted(SENSOR_BANDS, key=len, reverse=True):
        if name.endswith("_" + band):
            return name[:-len(band) - 1], band
    season, _, band = name.rpartition("_")
    return season, band


def _series_files(imaging: Path) -> list[tuple[str, str, Path]]:
    """(season, band, metrics CSV) of every imaged series, summer first."""
    out = []
    for f in sorted(imaging.glob("metrics_*.csv")):
        season, band = split_series_name(f.stem[len("metrics_"):])
        if band:
            out.append((season, band, f))
    order = {"summer": 0, "winter": 1}
    return sorted(out, key=lambda x: (order.get(x[0], 2), x[0], x[1]))


def _low_periods(t_h: np.ndarray, scr: np.ndarray, limit: float) -> list[tuple[float, float]]:
    """Runs of consecutive samples with SCR < ``limit`` as (first, last) sample times [h]."""
    low = np.asarray(scr) < limit
    runs, start = [], None
    for k, flag in enumerate(low):
        if flag and start is None:
            start = k
        if start is not None and (not flag or k == len(low) - 1):
            end = k if flag else k - 1
            runs.append((float(t_h[start]), float(t_h[end])))
            start = None
    return runs


def _between_frames(t_h, scr, contrast, cross_h) -> list[tuple[float, float]]:
    """Zero crossings of the contrast between two frames: ``(time [h], hours below the
    clutter limit)`` per sign change of ``contrast`` from one frame to the next.

    Between the frames the signed SCR (``scr`` with the contrast's sign) is taken as
    linear, so it passes through zero at ``t_k + dt |s_k| / (|s_k| + |s_k+1|)`` (or at the
    crossover of ``cross_h`` found in that interval, the imaging's interpolant) and stays
    below :data:`SCR_CLUTTER_LIMIT` for ``dt · 2 / (|s_k| + |s_k+1|)`` (at most ``dt``)
    where both frames lie above it.
    """
    out = []
    sign = np.sign(contrast)
    for k in np.flatnonzero(sign[:-1] * sign[1:] < 0):
        a, b = float(abs(scr[k])), float(abs(scr[k + 1]))
        dt = float(t_h[k + 1] - t_h[k])
        t0 = float(t_h[k]) + dt * a / (a + b) if a + b > 0 else float(t_h[k])
        inside = [c for c in cross_h if t_h[k] <= c <= t_h[k + 1]]
        if inside:
            t0 = float(inside[0])
        below = 0.0
        if a >= SCR_CLUTTER_LIMIT and b >= SCR_CLUTTER_LIMIT:
            below = min(dt, dt * 2.0 * SCR_CLUTTER_LIMIT / (a + b))
        out.append((t0, below))
    return out


def _collapsed_spread(m: pd.DataFrame) -> list[dict]:
    """Frames whose background spread collapsed (``std_background`` below
    :data:`SPREAD_COLLAPSE` of its running median over :data:`SPREAD_WINDOW_H`), each as
    ``{time_h, scr, std, median_std}``, highest SCR first; ``[]`` without the column."""
    if "std_background" not in m or len(m) < 3:
        return []
    t = m["time_h"].to_numpy(float)
    step = float(np.median(np.diff(t)))
    half = max(1, int(round(0.5 * SPREAD_WINDOW_H / step))) if step > 0 else 1
    std = m["std_background"].astype(float)
    med = std.rolling(2 * half + 1, center=True, min_periods=1).median().to_numpy()
    std = std.to_numpy()
    sel = np.flatnonzero((med > 0) & (std < SPREAD_COLLAPSE * med))
    rows = [dict(time_h=float(t[k]), scr=float(m["scr"].iloc[k]), std=float(std[k]),
                 median_std=float(med[k])) for k in sel]
    return sorted(rows, key=lambda r: -r["scr"])


def _crossing_sensitivity(m: pd.DataFrame, band: str, k: int) -> float:
    """How far an error of :data:`SENSITIVITY_K` in the ship's temperature relative to its
    surroundings moves the contrast's zero between frames ``k`` and ``k + 1`` [min]: that
    error over the rate at which the ship's mean temperature departs from the water's there
    (``ship_mean_temp`` − ``water_mean_temp``, central differences over the frames around
    the crossing). Linear: the contrast follows the temperature difference near its zero.
    NaN without those columns, inf when the difference does not change."""
    if not {"ship_mean_temp", "water_mean_temp"} <= set(m.columns):
        return float("nan")
    t = m["time_h"].to_numpy(float)
    d = m["ship_mean_temp"].to_numpy(float) - m["water_mean_temp"].to_numpy(float)
    a, b = max(k - 1, 0), min(k + 2, len(t) - 1)
    rate = abs(d[b] - d[a]) / max(t[b] - t[a], 1e-9)                      # [K h-1]
    return 60.0 * SENSITIVITY_K / rate if rate > 0 else float("inf")


def hardest_to_see(imaging: Path) -> pd.DataFrame:
    """Per season and band: the lowest SCR and its time, the low-SCR periods, the frame step.

    Columns ``season``, ``band``, ``scr_min`` [-], ``time_min_h`` [h], ``time_min`` (HH:MM),
    ``step_min`` (frame interval [min]), ``low_periods`` (HH:MM-HH:MM list where SCR <
    :data:`SCR_CLUTTER_LIMIT`), ``low_hours`` (their total length [h], counted as frames x
    frame interval), ``crossovers`` (HH:MM list of the contrast's zero crossings),
    ``zeros`` (``[(time [h], minutes per kelvin)]`` of every zero of the contrast between
    frames: :func:`_crossing_sensitivity`), ``collapsed`` (:func:`_collapsed_spread`).

    A crossover between two frames is a moment of zero contrast, hence of zero SCR, that
    the frames do not show (:func:`_between_frames`): it is the lowest SCR (0 at its time),
    a low period of its own when the frames around it lie above the limit, and its time
    below the limit is added to ``low_hours``.
    """
    cross = pd.DataFrame()
    if (imaging / "crossovers.csv").is_file():
        cross = strip_units(pd.read_csv(imaging / "crossovers.csv"))
    rows = []
    for season, band, f in _series_files(imaging):
        m = strip_units(pd.read_csv(f))
        if not len(m):
            continue
        t = m["time_h"].to_numpy(float)
        scr = m["scr"].to_numpy(float)
        if not np.isfinite(scr).any():
            continue
        k = int(np.nanargmin(scr))
        step = float(np.median(np.diff(t))) if t.size > 1 else float("nan")
        runs = _low_periods(t, scr, SCR_CLUTTER_LIMIT)
        n_low = int(np.sum(scr < SCR_CLUTTER_LIMIT))
        cx, cx_h = [], []
        if len(cross):
            sel = cross[(cross["season"] == season) & (cross["band"].astype(str) == band)]
            cx = list(sel["time_local"])
            cx_h = list(sel["time_h"]) if "time_h" in sel else []
        scr_min, t_min = float(scr[k]), float(t[k])
        low_hours = n_low * step
        zeros = []
        if "contrast" in m:
            found = _between_frames(t, scr, m["contrast"].to_numpy(float), cx_h)
            flips = np.flatnonzero(np.sign(m["contrast"].to_numpy(float))[:-1]
                                   * np.sign(m["contrast"].to_numpy(float))[1:] < 0)
            for (t0, below), kk in zip(found, flips):
                low_hours += below
                zeros.append((t0, _crossing_sensitivity(m, band, int(kk))))
                if not any(a - step <= t0 <= b + step for a, b in runs):
                    runs.append((t0, t0))
            if found:
                scr_min, t_min = 0.0, found[0][0]
            runs.sort()
        rows.append(dict(season=season, band=band, scr_min=scr_min,
                         time_min_h=t_min, time_min=_hhmm(t_min), step_min=step * 60.0,
                         low_periods=", ".join(_hhmm(a) if a == b else f"{_hhmm(a)}–{_hhmm(b)}"
                                              for a, b in runs)
                         or "none", low_hours=low_hours, crossovers=", ".join(cx) or "none",
                         zeros=zeros, collapsed=_collapsed_spread(m)))
    return pd.DataFrame(rows)


def _clock_of(summary: dict, season: str) -> str:
    """``"UTC+8 (Etc/GMT-8)"`` of a season's local clock, from the imaging summary."""
    sc = (summary.get("scenarios") or {}).get(season) or {}
    if sc.get("date") and sc.get("tz"):
        return zone_text(str(sc["date"]), str(sc["tz"]))
    return ""


def _minutes(x: float) -> str:
    """A time shift [min] as the answer box prints it (``"24 min"``, ``"> 2 h"``)."""
    if not np.isfinite(x) or x >= 120:
        return "> 2 h"
    return "< 1 min" if x < 1.0 else f"{x:.0f} min"


def _ensemble_lines(run: Path) -> list[str]:
    """A weather ensemble's crossover times (median, 5–95 %) as sentences, when the run
    has ``ensemble/crossovers.csv``."""
    f = run / "ensemble" / "crossovers.csv"
    if not f.is_file():
        return []
    d = strip_units(pd.read_csv(f, dtype=str))
    out = []
    for _, r in d.iterrows():
        out.append(f"{r.get('season')} {band_label(r.get('band'))}, {r.get('direction')} "
                   f"crossover #{r.get('order')}: median {r.get('median')}, 5–95 % "
                   f"{r.get('p05')}–{r.get('p95')} over {r.get('members')} of "
                   f"{r.get('of')} weather members")
    return out


def _answer_table(df: pd.DataFrame, zone: str) -> str:
    """The per-band summary as a table whose rows stack into labelled blocks on a narrow
    screen (each cell carries its column name in ``data-label``)."""
    cols = [("season", "season"), ("band", "band"), ("scr_min", "lowest SCR [-]"),
            ("time_min", f"at ({zone or 'local'})"),
            ("low_periods", f"SCR < {SCR_CLUTTER_LIMIT:g}"),
            ("low_hours", f"hours with SCR < {SCR_CLUTTER_LIMIT:g} [h]"),
            ("crossovers", "thermal crossovers")]
    head = "".join(f"<th>{html.escape(lab)}</th>" for _, lab in cols)
    body = []
    for _, r in df.iterrows():
        cells = []
        for key, lab in cols:
            v = r[key]
            text = band_label(v) if key == "band" else (f"{v:.3g}" if isinstance(
                v, (float, np.floating)) else str(v))
            cells.append(f'<td data-label="{html.escape(lab)}">{html.escape(text)}</td>')
        body.append("<tr>" + "".join(cells) + "</tr>")
    return (f'<table class="answer-table"><thead><tr>{head}</tr></thead>'
            f"<tbody>{''.join(body)}</tbody></table>")


def first_screen(run: Path) -> str:
    """The opening block of the report: when, in which band, how sure (HTML)."""
    imaging = run / "imaging"
    ensemble = _ensemble_lines(run)
    df = hardest_to_see(imaging) if imaging.is_dir() else pd.DataFrame()
    if not len(df):
        if not ensemble:
            return ""
        return ('<section id="answer" class="answer"><h2>When is the ship hardest to see?</h2>'
                "<p>Crossover times over the weather ensemble (local clock):</p><ul>"
                + "".join(f"<li>{html.escape(x)}</li>" for x in ensemble) + "</ul></section>")
    summary = {}
    if (imaging / "summary.json").is_file():
        summary = json.loads((imaging / "summary.json").read_text(encoding="utf-8"))
    parts = ['<section id="answer" class="answer"><h2>When is the ship hardest to see?</h2>']
    zones = []
    for season, g in df.groupby("season", sort=False):
        best = g.loc[g["scr_min"].idxmin()]
        others = g[g["band"] != best["band"]]
        sc = (summary.get("scenarios") or {}).get(season, {})
        zone = _clock_of(summary, season)
        zones.append(zone)
        where = ""
        if sc:
            where = (f" ({sc.get('date')}, {latitude_text(sc['latitude'])} "
                     f"{longitude_text(sc['longitude'])})")
        local = f"local ({zone.split(' ')[0]})" if zone else "local"
        parts.append(
            f'<p class="headline"><b>{html.escape(season)}{html.escape(where)}:</b> hardest '
            f"at <b>{best['time_min']}</b> {html.escape(local)} in the "
            f"<b>{html.escape(band_label(best['band']))}</b> band, local SCR "
            f"{best['scr_min']:.2g}"
            + (" (a thermal crossover: zero contrast)" if best["scr_min"] == 0 else "")
            + ".</p>")
        if zone:
            parts.append(f'<p class="zone">Times are local = {html.escape(zone)}.</p>')
        if sc.get("background"):
            bg = str(sc["background"])
            what = ("a synthetic port, not a real place" if "synthetic" in bg
                    else "a real scene")
            parts.append(f'<p class="background"><b>Background: {html.escape(what)}</b> — '
                         f"{html.escape(bg)}</p>")
        sure = [f"frame spacing: time to ±{best['step_min'] / 2:.0f} min (frames every "
                f"{best['step_min']:.0f} min)"]
        if ensemble:
            sure += [f"weather uncertainty: {x}" for x in ensemble if x.startswith(season)]
        for _, r in g.iterrows():
            if r["zeros"]:
                each = ", ".join(f"{_hhmm(t0)} ±{_minutes(per_k)}" for t0, per_k in r["zeros"])
                sure.append(f"{band_label(r['band'])} crossovers {each} per "
                            f"{SENSITIVITY_K:g} K error in the ship's temperature relative to "
                            "its surroundings (linear: that error over the rate at which ship "
                            "and water temperatures part)")
        if not ensemble and any(len(r["zeros"]) for _, r in g.iterrows()):
            sure.append("for the spread under the weather's uncertainty (cloud, wind, air), "
                        "run `shipthermal ensemble` on this scenario")
        if best["low_periods"] != "none":
            sure.append(f"SCR below {SCR_CLUTTER_LIMIT:g} (contrast under the background "
                        f"clutter) during {best['low_periods']}, {best['low_hours']:.1f} h "
                        "in all")
        else:
            sure.append(f"the SCR never falls below {SCR_CLUTTER_LIMIT:g}: the ship stays "
                        "above the background clutter all day")
        for _, r in g.iterrows():
            if r["collapsed"]:
                top = r["collapsed"][0]
                sure.append(
                    f"{band_label(r['band'])}: the SCR peak of {top['scr']:.3g} at "
                    f"{_hhmm(top['time_h'])} (and {len(r['collapsed']) - 1} more frames "
                    "marked ▼ on the chart) is the background's spread collapsing to "
                    f"{top['std']:.2g} {_R_UNIT} ({100 * top['std'] / top['median_std']:.0f} % "
                    f"of its median over {SPREAD_WINDOW_H:g} h): the surroundings are "
                    "momentarily uniform, the ship is not brighter")
        for _, o in others.iterrows():
            if best["scr_min"] > 0:
                ratio = (f"{o['scr_min'] / best['scr_min']:.1f}× the "
                         f"{band_label(best['band'])} minimum")
            else:
                ratio = ("a crossover too" if o["scr_min"] == 0 else
                         f"the {band_label(best['band'])} band reaches 0 at a crossover")
            sure.append(f"the {band_label(o['band'])} band's lowest SCR is {o['scr_min']:.2g} "
                        f"at {o['time_min']} ({ratio})")
        src = (summary.get("ship_temperatures") or {}).get(season)
        if src:
            sure.append(f"ship temperatures: {src}")
        parts.append("<h3 class=\"sure\">How sure</h3><ul>"
                     + "".join(f"<li>{html.escape(x)}</li>" for x in sure) + "</ul>")
        series = [(r["band"], strip_units(pd.read_csv(
            imaging / f"metrics_{season}_{r['band']}.csv")), r) for _, r in g.iterrows()]
        parts.append(_scr_chart(series, f"{season}: local SCR, both bands", zone))
    for f in sorted((run / "thermal").glob("*/thermal_summary.json")):
        th = json.loads(f.read_text(encoding="utf-8"))
        changes = [c for c in th.get("day_changes_K", []) if c is not None]
        if th.get("converged") is False:
            parts.append(f'<p class="note">Caution: the thermal spin-up of '
                         f"{html.escape(f.parent.name)} did not converge"
                         + (f" (last day-to-day change {changes[-1]:.3g} K, tolerance "
                            f"{th.get('spinup_tolerance_K')} K)" if changes else "")
                         + ": the ship temperatures, hence these times, may still drift.</p>")
    parts.append(_answer_table(df, "/".join(dict.fromkeys(z.split(" ")[0] for z in zones if z))))
    parts.append('<p class="note">Local SCR = |mean ship − mean local background| / standard '
                 "deviation of the background (paper eq. 22), from the at-aperture images. "
                 '<a href="#day">Explore the day</a> · <a href="#data">Download the '
                 "data</a>.</p></section>")
    return "".join(parts)


# ---------------------------------------------------------------- frames


def _colourise(img: np.ndarray, vmin: float, vmax: float, cmap: str = "inferno"):
    # lazy: matplotlib takes most of a second to import (measured)
    from matplotlib import colormaps

    x = np.clip((img - vmin) / (vmax - vmin if vmax > vmin else 1.0), 0.0, 1.0)
    return (colormaps[cmap](x)[..., :3] * 255).astype(np.uint8)


def _png_rgb(rgb: np.ndarray, zoom: int = 1, boxes=()) -> bytes:
    """PNG of an RGB array enlarged by ``zoom`` (nearest) with rectangles drawn on it;
    ``boxes``: ((row0, row1, col0, col1), colour) in source pixels, half-open."""
    # lazy: Pillow, only for the pictures of an imaged run
    from PIL import Image, ImageDraw

    im = Image.fromarray(rgb).resize((rgb.shape[1] * zoom, rgb.shape[0] * zoom),
                                     Image.NEAREST)
    d = ImageDraw.Draw(im)
    for (r0, r1, c0, c1), colour in boxes:
        d.rectangle([c0 * zoom, r0 * zoom, c1 * zoom - 1, r1 * zoom - 1], outline=colour,
                    width=1)
    buf = io.BytesIO()
    im.save(buf, format="PNG", optimize=True)
    return buf.getvalue()


def _colourbar_png(vmin: float, vmax: float, label: str, cmap: str = "inferno",
                   second=None) -> bytes:
    """A horizontal colour bar [label]; ``second``: (function, label) of a second scale
    drawn on the top edge (e.g. apparent temperature)."""
    # lazy: matplotlib takes most of a second to import (measured)
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.colors import Normalize

    fig = plt.figure(figsize=(3.4, 1.1 if second else 0.7), dpi=90)
    ax = fig.add_axes([0.05, 0.42 if second else 0.55, 0.9, 0.16 if second else 0.2])
    cb = fig.colorbar(plt.cm.ScalarMappable(Normalize(vmin, vmax), cmap), cax=ax,
                      orientation="horizontal")
    cb.set_label(label, fontsize=7)
    cb.ax.tick_params(labelsize=6)
    if second is not None:
        fn, lab = second
        ticks = cb.ax.get_xticks()
        ticks = ticks[(ticks >= vmin) & (ticks <= vmax)]
        top = cb.ax.secondary_xaxis("top")
        top.set_xticks(ticks)
        top.set_xticklabels([f"{fn(v):.1f}" for v in ticks], fontsize=6)
        top.set_xlabel(lab, fontsize=7)
    buf = io.BytesIO()
    fig.savefig(buf, format="png")
    plt.close(fig)
    return buf.getvalue()


def _nearest(times_h: np.ndarray, hour: float) -> int:
    return int(np.argmin(np.abs(np.asarray(times_h) - hour)))


def _image_frames(nc: Path, band: str, hours=SLIDER_HOURS):
    """(list of PNG data URIs per slider time ``hours``, colour-bar PNG, caption) of one
    series."""
    # deferred: xarray takes 0.16 s to import (measured); only a run with images needs it
    import xarray as xr

    with xr.open_dataset(nc, engine="h5netcdf") as ds:
        rad = ds["radiance"].values
        bt = (ds["brightness_temperature"].values if "brightness_temperature" in ds.variables
              else None)
        cov = ds["coverage"].values
        # hours after local midnight (files written before CF time: "time" itself)
        th = (ds["time_local_h"] if "time_local_h" in ds.variables else ds["time"]).values
        th = th.astype(float)
        x = ds["x"].values
    mask = cov > 0
    res = float(abs(x[1] - x[0])) if x.size > 1 else float("nan")
    ny, nx = mask.shape
    if mask.any():
        rows, cols = np.flatnonzero(mask.any(axis=1)), np.flatnonzero(mask.any(axis=0))
        rc, cc = (rows[0] + rows[-1] + 1) // 2, (cols[0] + cols[-1] + 1) // 2
    else:
        rc, cc = ny // 2, nx // 2
    h, w = min(_CROP_PX, ny), min(_CROP_PX, nx)
    r0 = int(np.clip(rc - h // 2, 0, ny - h))
    c0 = int(np.clip(cc - w // 2, 0, nx - w))
    ks = [_nearest(th, hr) for hr in hours]
    stack = rad[ks, r0:r0 + h, c0:c0 + w]
    vmin, vmax = np.nanpercentile(stack, _CLIM_PERCENTILES)
    boxes = []
    if mask.any():
        sub = mask[r0:r0 + h, c0:c0 + w]
        rr, cc_ = np.flatnonzero(sub.any(axis=1)), np.flatnonzero(sub.any(axis=0))
        if rr.size:
            boxes.append(((rr[0], rr[-1] + 1, cc_[0], cc_[-1] + 1), (0, 230, 255)))
            wr0, wr1, wc0, wc1 = background_window(mask)
            boxes.append(((wr0 - r0, wr1 - r0, wc0 - c0, wc1 - c0), (255, 255, 255)))
    uris = [_b64png(_png_rgb(_colourise(f, vmin, vmax), _ZOOM, boxes)) for f in stack]
    if bt is not None:   # the product's own brightness temperature (K1/K2, a user band)
        ok = np.isfinite(rad) & np.isfinite(bt)
        order = np.argsort(rad[ok], kind="stable")
        rs, bs = rad[ok][order], bt[ok][order]
        second = (lambda L: float(np.interp(L, rs, bs)),
                  "brightness temperature at the aperture [K]")
    else:
        second = (lambda L: float(brightness_temperature(L, band)),
                  "apparent temperature at the aperture [K]")
    bar = _colourbar_png(float(vmin), float(vmax), f"at-aperture radiance {band_label(band)} "
                         f"[{_R_UNIT}]", second=second)
    cap = (f"{h * res / 1000:.1f} km × {w * res / 1000:.1f} km around the ship "
           f"({res:g} m pixels); cyan: ship pixels (target), white: local background window "
           "of the SCR")
    return uris, bar, cap


def _surface_frames(case_dir: Path, title: str, hours=SLIDER_HOURS, zone: str = ""):
    """(PNG data URIs per slider time ``hours``, caption) of the ship coloured by its surface
    temperature, one colour scale over the day (a weather record's first day).

    The triangles are drawn once, each in a colour that encodes its index; every frame is
    then that picture of indices coloured by the frame's temperatures, shown as an image in
    the same axes (:func:`~shipthermal.figures.polygon_index_raster`). The 25 frames of
    the default ship (60,000 triangles): 1.7 s, against 3.3 s drawing every triangle for
    every frame."""
    # lazy: matplotlib takes most of a second to import (measured)
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    hist = load_history(case_dir)
    v, f = hist.vertices, hist.faces
    th = hist.times_s / 3600.0
    ks = [_nearest(th % 24.0 if th[-1] > 24.0 + 1e-9 else th, hr) for hr in hours]
    # only the rows shown (a record's are read from its file)
    temp = {k: np.asarray(hist.face_temperature[k], dtype=float) for k in set(ks)}
    vmin, vmax = np.nanpercentile(np.stack([temp[k] for k in ks]), [0.5, 99.5])
    fig, ax, coll, ttl, order = surface_frame_figure(v, f, vmin, vmax)
    shown = polygon_index_raster(fig, ax, coll)         # triangle (in ``order``) per pixel
    coll.set_visible(False)
    image = ax.imshow(np.zeros(shown.shape + (4,)), extent=(*ax.get_xlim(), *ax.get_ylim()),
                      interpolation="nearest", origin="upper")
    hit = shown >= 0
    uris = []
    for hr, k in zip(hours, ks):
        rgba = np.zeros(shown.shape + (4,))
        rgba[hit] = coll.to_rgba(temp[k][order][shown[hit]])
        image.set_data(rgba)
        ttl.set_text(f"{title}, {_hhmm(th[k] % 24 if th[k] < 24 - 1e-9 else th[k])} local"
                     + (f" ({zone})" if zone else ""))
        buf = io.BytesIO()
        fig.savefig(buf, format="png")
        uris.append(_b64png(buf.getvalue()))
    plt.close(fig)
    return uris, (f"one colour scale for the whole day ({vmin:.1f}–{vmax:.1f} K); oblique view "
                  "from the starboard quarter, bow to the right")


_DASH = {"-": "", "--": "6 3", "-.": "6 2 1 2", ":": "1 2"}


def _scr_chart(series, label: str, zone: str = "", hours=None) -> str:
    """Inline SVG of the local SCR of every band of one season over the day on a log scale:
    each band its colour and dash pattern, SCR = 1 marked, crossovers as thin grey lines,
    frames whose background spread collapsed marked ▼ (:func:`_collapsed_spread`).

    ``series``: ``[(band, metrics, hardest_to_see row)]``. ``hours``: the slider's times;
    with them, a cursor line and the SCR values at each slider time that the script moves.
    """
    W, H, L, R, T, B = 600, 210, 46, 12, 34, 30
    scrs = [np.clip(m["scr"].to_numpy(float), 1e-3, None) for _, m, _ in series]
    finite = np.concatenate([x[np.isfinite(x)] for x in scrs] + [np.array([1.0])])
    lo = np.floor(np.log10(max(float(np.min(finite)), 1e-3)))
    hi = np.ceil(np.log10(max(float(np.max(finite)), 10.0 ** (lo + 1))))
    span = max([24.0] + [float(np.nanmax(m["time_h"])) for _, m, _ in series if len(m)])
    sx = (W - L - R) / span

    def X(h):
        return L + h * sx

    def Y(v):
        return T + (hi - np.log10(v)) / (hi - lo) * (H - T - B)

    g = [f'<svg class="scr" width="{W}" height="{H}" viewBox="0 0 {W} {H}" role="img" '
         f'aria-label="{html.escape(label)}">',
         f'<text x="{L}" y="12" font-size="11">{html.escape(label)}</text>']
    for e in range(int(lo), int(hi) + 1):
        y = Y(10.0 ** e)
        g.append(f'<line x1="{L}" x2="{W - R}" y1="{y:.1f}" y2="{y:.1f}" stroke="#ddd"/>'
                 f'<text x="{L - 4}" y="{y + 3:.1f}" font-size="9" text-anchor="end">'
                 f"{10.0 ** e:g}</text>")
    if lo <= 0 <= hi:
        y = Y(SCR_CLUTTER_LIMIT)
        g.append(f'<line x1="{L}" x2="{W - R}" y1="{y:.1f}" y2="{y:.1f}" stroke="#000" '
                 'stroke-width="1" stroke-dasharray="1 3"/>'
                 f'<text x="{L + 3}" y="{y - 3:.1f}" font-size="9">'
                 f"SCR = {SCR_CLUTTER_LIMIT:g}: contrast = clutter</text>")
    step = 3 if span <= 24.0 else 24 * max(1, round(span / 24 / 12))
    for h in np.arange(0.0, span + 1e-9, step):
        text = f"{int(h):02d}" if span <= 24.0 else f"d{int(h // 24) + 1}"
        g.append(f'<text x="{X(h):.1f}" y="{H - 16}" font-size="9" text-anchor="middle">'
                 f"{text}</text>")
    g.append(f'<text x="{(L + W - R) / 2}" y="{H - 3}" font-size="9" text-anchor="middle">'
             + html.escape(("local time [h]" if span <= 24.0 else "day of the record")
                           + (f", {zone.split(' ')[0]}" if zone else "")
                           + "; SCR [-], log scale; grey: crossovers; ▼ spread collapsed")
             + "</text>")
    legend_x = L + 180
    for (band, m, row), scr in zip(series, scrs):
        colour, ls = BAND_STYLES.get(band, (OKABE_ITO["black"], "-"))
        dash = _DASH.get(ls, "") if isinstance(ls, str) else ""
        dash_attr = f' stroke-dasharray="{dash}"' if dash else ""
        for t0, _ in row["zeros"]:
            g.append(f'<line x1="{X(t0):.1f}" x2="{X(t0):.1f}" y1="{T}" y2="{H - B}" '
                     'stroke="#999" stroke-width="0.8"/>')
        t = m["time_h"].to_numpy(float)
        pts = " ".join(f"{X(a):.1f},{Y(b):.1f}" for a, b in zip(t, scr) if np.isfinite(b))
        g.append(f'<polyline fill="none" stroke="{colour}" stroke-width="1.8"{dash_attr} '
                 f'points="{pts}"/>')
        for c in row["collapsed"]:
            g.append(f'<text x="{X(c["time_h"]):.1f}" y="{T - 3}" font-size="9" '
                     f'text-anchor="middle" fill="{colour}">▼</text>')
        g.append(f'<line x1="{legend_x}" x2="{legend_x + 22}" y1="9" y2="9" stroke="{colour}" '
                 f'stroke-width="2"{dash_attr}/><text x="{legend_x + 26}" y="12" '
                 f'font-size="10">{html.escape(band_label(band))}</text>')
        legend_x += 90
    if hours is not None:
        vals = []
        for hr in hours:
            bits = []
            for (band, m, _), scr in zip(series, scrs):
                v = float(scr[_nearest(m["time_h"].to_numpy(float), hr)])
                bits.append(f"{band_label(band).replace(' µm', '')}: "
                            + (f"{v:.2g}" if v < 10 else f"{v:.0f}"))
            vals.append("SCR " + ", ".join(bits))
        g.append(f'<line class="cursor" data-x0="{L}" data-dx="{sx:.5f}" x1="{L}" x2="{L}" '
                 f'y1="{T}" y2="{H - B}" stroke="#cf222e" stroke-width="2"/>')
        g.append(f'<text class="cursor-value" data-values="{html.escape(json.dumps(vals))}" '
                 f'x="{W - R}" y="26" font-size="10" text-anchor="end" fill="#cf222e"></text>')
    g.append("</svg>")
    return "".join(g)


def _frame_group(uris: list[str], alt: str, hours, start: int) -> str:
    return "".join(f'<img data-frame="{i}" alt="{html.escape(alt)} {_hhmm(h)}" src="{u}"'
                   + ("" if i == start else " hidden") + ">"
                   for i, (h, u) in enumerate(zip(hours, uris)))


def key_moments(df: pd.DataFrame) -> list[tuple[str, float]]:
    """``(label, hour)`` of the moments worth a look on the first day: each band's lowest
    SCR and every crossover."""
    out = []
    for _, r in df.iterrows():
        tag = f"{r['season']} {band_label(r['band'])}"
        if r["time_min_h"] <= 24.0:
            out.append((f"lowest SCR {r['time_min']} ({tag})", float(r["time_min_h"])))
        for t0, _ in r["zeros"]:
            if t0 <= 24.0 and abs(t0 - r["time_min_h"]) > 1e-9:
                out.append((f"crossover {_hhmm(t0)} ({tag})", float(t0)))
    return out


def slider_hours(df: pd.DataFrame, frames_h=None) -> list[float]:
    """The slider's times [h]: every hour of the day and each key moment
    (:func:`key_moments`) on the frame nearest to it (``frames_h``: the frames' times)."""
    hours = {float(h) for h in SLIDER_HOURS}
    frames = np.asarray(frames_h if frames_h is not None else [], float)
    for _, h in key_moments(df) if len(df) else []:
        hours.add(float(frames[_nearest(frames, h)]) if frames.size else round(h * 60) / 60)
    return sorted(round(h * 3600.0) / 3600.0 for h in hours)


def day_section(run: Path) -> str:
    """The slider section (HTML), or "" when the run has neither images nor a history."""
    imaging = run / "imaging"
    df = hardest_to_see(imaging) if imaging.is_dir() else pd.DataFrame()
    summary = {}
    if (imaging / "summary.json").is_file():
        summary = json.loads((imaging / "summary.json").read_text(encoding="utf-8"))
    files = _series_files(imaging) if imaging.is_dir() else []
    frames_h = (strip_units(pd.read_csv(files[0][2]))["time_h"].to_numpy(float) if files
                else None)
    hours = slider_hours(df, frames_h)
    start = hours.index(12.0)
    zones = []
    blocks = []
    for season in dict.fromkeys(s for s, _, _ in files):
        zone = _clock_of(summary, season)
        zones.append(zone)
        figs, series = [], []
        for s_, band, f in files:
            if s_ != season:
                continue
            nc = imaging / f"images_{season}_{band}.nc"
            if nc.is_file():
                uris, bar, cap = _image_frames(nc, band, hours)
                figs.append(f'<figure class="frames">'
                            f'{_frame_group(uris, f"{season} {band_label(band)}", hours, start)}'
                            f'<img alt="colour bar {season} {band_label(band)}" '
                            f'src="{_b64png(bar)}">'
                            f"<figcaption>{html.escape(band_label(band))}: {html.escape(cap)}; "
                            "one colour scale for the whole day</figcaption></figure>")
            row = df[(df["season"] == season) & (df["band"] == band)]
            if len(row):
                series.append((band, strip_units(pd.read_csv(f)), row.iloc[0]))
        if series:
            figs.append(_scr_chart(series, f"{season}: local SCR, both bands", zone, hours))
        blocks.append(f"<h3>{html.escape(season)}</h3>"
                      f'<div class="row">{"".join(figs)}</div>')
    thermal = run / "thermal"
    zone = next((z for z in zones if z), "")
    if thermal.is_dir():
        for d in sorted(p for p in thermal.iterdir() if p.is_dir()):
            if history_file(d).is_file():
                uris, cap = _surface_frames(d, d.name, hours,
                                            zone.split(" ")[0] if zone else "")
                blocks.append(f"<h3>{html.escape(d.name)}: ship surface temperature</h3>"
                              f'<figure class="frames">'
                              f"{_frame_group(uris, d.name, hours, start)}"
                              f"<figcaption>{html.escape(cap)}</figcaption></figure>")
    if not blocks:
        return ""
    labels = json.dumps([_hhmm(h) for h in hours])
    jumps = "".join(
        f'<button type="button" data-jump="{hours.index(min(hours, key=lambda x: abs(x - h)))}">'
        f"{html.escape(lab)}</button>" for lab, h in key_moments(df)) if len(df) else ""
    local = f"local ({zone})" if zone else "local"
    control = (f'<div class="slider"><button type="button" id="day-play">play</button> '
               '<button type="button" id="day-prev" aria-label="previous frame">◀</button>'
               f'<input type="range" id="day-slider" min="0" max="{len(hours) - 1}" '
               f'step="1" value="{start}" aria-label="local time" '
               f'data-labels="{html.escape(labels)}" '
               f'data-hours="{html.escape(json.dumps([round(h, 6) for h in hours]))}">'
               '<button type="button" id="day-next" aria-label="next frame">▶</button> '
               f'<output id="day-time">12:00</output> {html.escape(local)}'
               + (f'<div class="jumps">Jump to: {jumps}</div>' if jumps else "") + "</div>")
    return control + "".join(blocks)


#: The report's only script: moves every frame group, SCR cursor and label to the slider's
#: time; the play button steps through the day, ◀ ▶ one frame, the jump buttons go to the
#: lowest SCR and each crossover.
SCRIPT = """
(function(){
var s=document.getElementById('day-slider');if(!s)return;
var labels=JSON.parse(s.getAttribute('data-labels')),hours=JSON.parse(s.getAttribute('data-hours')),
out=document.getElementById('day-time');
function show(i){
 out.textContent=labels[i];
 document.querySelectorAll('img[data-frame]').forEach(function(e){
  e.hidden=(+e.getAttribute('data-frame'))!==i;});
 document.querySelectorAll('line.cursor').forEach(function(l){
  var x=(+l.getAttribute('data-x0'))+hours[i]*(+l.getAttribute('data-dx'));
  l.setAttribute('x1',x);l.setAttribute('x2',x);});
 document.querySelectorAll('text.cursor-value').forEach(function(t){
  t.textContent=labels[i]+'  '+JSON.parse(t.getAttribute('data-values'))[i];});
 document.body.setAttribute('data-shown',labels[i]);
}
function go(i){s.value=(i+labels.length)%labels.length;show(+s.value);}
s.addEventListener('input',function(){show(+s.value);});
document.getElementById('day-prev').addEventListener('click',function(){go(+s.value-1);});
document.getElementById('day-next').addEventListener('click',function(){go(+s.value+1);});
document.querySelectorAll('button[data-jump]').forEach(function(b){
 b.addEventListener('click',function(){go(+b.getAttribute('data-jump'));});});
var timer=null,btn=document.getElementById('day-play');
btn.addEventListener('click',function(){
 if(timer){clearInterval(timer);timer=null;btn.textContent='play';return;}
 btn.textContent='pause';
 timer=setInterval(function(){go(+s.value+1);},700);});
show(+s.value);
})();
"""
