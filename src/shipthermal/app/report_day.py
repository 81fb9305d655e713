"""The day as it unfolds, for the HTML report: a first screen and a time slider.

Built from the files of a run directory only:

* ``imaging/metrics_<season>_<band>.csv`` — SCR and contrast over the day;
* ``imaging/images_<season>_<band>.nc`` — the at-aperture radiance stack around the ship;
* ``thermal/<case>/history.npz`` — the ship's outer-surface temperature over the day
  (``history.h5`` for a weather record: its first day is shown).

The first screen answers *when is the ship hardest to see, in which band, and how sure is
that*: the time of the lowest local SCR (paper eq. 22) per season and band, the periods
in which the SCR is below :data:`SCR_CLUTTER_LIMIT` (the target-background contrast is
smaller than the background's own standard deviation), and what the answer rests on
(frame interval, margin to the other band, where the ship temperatures come from).

The slider section holds one frame per hour for every season and band (one colour scale per
band and season, shared by all hours) and for the ship's surface temperature (one scale per
case), and the SCR curves as inline SVG with a cursor at the chosen hour. Everything is
embedded (PNG ``data:`` URIs, inline SVG, one small inline script); no external URL.
"""

from __future__ import annotations

import base64
import html
import io
import json
from pathlib import Path

import numpy as np
import pandas as pd

from .html_table import html_table
from .pipeline import history_file, load_history

__all__ = ["SCR_CLUTTER_LIMIT", "SLIDER_HOURS", "hardest_to_see", "first_screen",
           "day_section", "SCRIPT"]

#: SCR below which the ship's mean contrast to its local background is smaller than the
#: background's standard deviation (eq. 22: SCR = |contrast| / std_background) [-].
SCR_CLUTTER_LIMIT = 1.0

#: Hours of the slider [h after local midnight].
SLIDER_HOURS = tuple(range(25))

#: Side of the image crop shown around the ship [pixels] and its enlargement factor [-].
_CROP_PX = 40
_ZOOM = 5

#: Percentiles of the shared colour scale of the image frames (as the panel figures) [%].
_CLIM_PERCENTILES = (1.0, 99.5)


def _b64png(png: bytes) -> str:
    return "data:image/png;base64," + base64.b64encode(png).decode("ascii")


def _hhmm(hours: float) -> str:
    m = int(round(hours * 60.0))
    return f"{(m // 60) % 24:02d}:{m % 60:02d}" if m < 1440 else "24:00"


def _series_files(imaging: Path) -> list[tuple[str, str, Path]]:
    """(season, band, metrics CSV) of every imaged series, summer first."""
    out = []
    for f in sorted(imaging.glob("metrics_*.csv")):
        season, _, band = f.stem[len("metrics_"):].partition("_")
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


def hardest_to_see(imaging: Path) -> pd.DataFrame:
    """Per season and band: the lowest SCR and its time, the low-SCR periods, the frame step.

    Columns ``season``, ``band``, ``scr_min`` [-], ``time_min_h`` [h], ``time_min`` (HH:MM),
    ``step_min`` (frame interval [min]), ``low_periods`` (HH:MM-HH:MM list where SCR <
    :data:`SCR_CLUTTER_LIMIT`), ``low_hours`` (their total length [h], counted as frames x
    frame interval), ``crossovers`` (HH:MM list of the contrast's zero crossings).

    A crossover between two frames is a moment of zero contrast, hence of zero SCR, that
    the frames do not show (:func:`_between_frames`): it is the lowest SCR (0 at its time),
    a low period of its own when the frames around it lie above the limit, and its time
    below the limit is added to ``low_hours``.
    """
    cross = pd.DataFrame()
    if (imaging / "crossovers.csv").is_file():
        cross = pd.read_csv(imaging / "crossovers.csv")
    rows = []
    for season, band, f in _series_files(imaging):
        m = pd.read_csv(f)
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
        if "contrast" in m:
            zeros = _between_frames(t, scr, m["contrast"].to_numpy(float), cx_h)
            for t0, below in zeros:
                low_hours += below
                if not any(a - step <= t0 <= b + step for a, b in runs):
                    runs.append((t0, t0))
            if zeros:
                scr_min, t_min = 0.0, zeros[0][0]
            runs.sort()
        rows.append(dict(season=season, band=band, scr_min=scr_min,
                         time_min_h=t_min, time_min=_hhmm(t_min), step_min=step * 60.0,
                         low_periods=", ".join(_hhmm(a) if a == b else f"{_hhmm(a)}–{_hhmm(b)}"
                                              for a, b in runs)
                         or "none", low_hours=low_hours, crossovers=", ".join(cx) or "none"))
    return pd.DataFrame(rows)


def first_screen(run: Path) -> str:
    """The opening block of the report: when, in which band, how sure (HTML)."""
    imaging = run / "imaging"
    if not imaging.is_dir():
        return ""
    df = hardest_to_see(imaging)
    if not len(df):
        return ""
    summary = {}
    if (imaging / "summary.json").is_file():
        summary = json.loads((imaging / "summary.json").read_text(encoding="utf-8"))
    parts = ['<section id="answer" class="answer"><h2>When is the ship hardest to see?</h2>']
    for season, g in df.groupby("season", sort=False):
        best = g.loc[g["scr_min"].idxmin()]
        others = g[g["band"] != best["band"]]
        sc = (summary.get("scenarios") or {}).get(season, {})
        where = ""
        if sc:
            lat, lon = sc.get("latitude"), sc.get("longitude")
            where = (f" ({sc.get('date')}, {abs(lat):.2f} {'N' if lat >= 0 else 'S'} "
                     f"{abs(lon):.2f} {'E' if lon >= 0 else 'W'})")
        parts.append(
            f'<p class="headline"><b>{html.escape(season)}{html.escape(where)}:</b> hardest '
            f"at <b>{best['time_min']}</b> local in the <b>{html.escape(best['band'])} µm</b> "
            f"band, local SCR {best['scr_min']:.2g}.</p>")
        sure = [f"time to ±{best['step_min'] / 2:.0f} min (frames every "
                f"{best['step_min']:.0f} min)"]
        if best["low_periods"] != "none":
            sure.append(f"SCR below {SCR_CLUTTER_LIMIT:g} (contrast under the background "
                        f"clutter) during {best['low_periods']}, {best['low_hours']:.1f} h "
                        "in all")
        else:
            sure.append(f"the SCR never falls below {SCR_CLUTTER_LIMIT:g}: the ship stays "
                        "above the background clutter all day")
        for _, o in others.iterrows():
            ratio = o["scr_min"] / best["scr_min"] if best["scr_min"] > 0 else float("inf")
            sure.append(f"the {o['band']} µm band's lowest SCR is {o['scr_min']:.2g} at "
                        f"{o['time_min']} ({ratio:.1f}× the {best['band']} µm minimum)")
        src = (summary.get("ship_temperatures") or {}).get(season)
        if src:
            sure.append(f"ship temperatures: {src}")
        if sc.get("background"):
            sure.append(f"background: {sc['background']}")
        parts.append("<ul>" + "".join(f"<li>{html.escape(s)}</li>" for s in sure) + "</ul>")
    for f in sorted((run / "thermal").glob("*/thermal_summary.json")):
        th = json.loads(f.read_text(encoding="utf-8"))
        changes = [c for c in th.get("day_changes_K", []) if c is not None]
        if th.get("converged") is False:
            parts.append(f'<p class="note">Caution: the thermal spin-up of '
                         f"{html.escape(f.parent.name)} did not converge"
                         + (f" (last day-to-day change {changes[-1]:.3g} K, tolerance "
                            f"{th.get('spinup_tolerance_K')} K)" if changes else "")
                         + ": the ship temperatures, hence these times, may still drift.</p>")
    show = df[["season", "band", "scr_min", "time_min", "low_periods", "low_hours",
               "crossovers"]].rename(columns={
                   "scr_min": "lowest SCR [-]", "time_min": "at (local)",
                   "low_periods": f"SCR < {SCR_CLUTTER_LIMIT:g}",
                   "low_hours": f"hours with SCR < {SCR_CLUTTER_LIMIT:g} [h]",
                   "crossovers": "thermal crossovers"})
    parts.append(html_table(show, "{:.3g}"))
    parts.append('<p class="note">Local SCR = |mean ship − mean local background| / standard '
                 "deviation of the background (paper eq. 22), from the at-aperture images. "
                 '<a href="#day">Explore the day</a>.</p></section>')
    return "".join(parts)


# ---------------------------------------------------------------- frames


def _colourise(img: np.ndarray, vmin: float, vmax: float, cmap: str = "inferno"):
    from matplotlib import colormaps

    x = np.clip((img - vmin) / (vmax - vmin if vmax > vmin else 1.0), 0.0, 1.0)
    return (colormaps[cmap](x)[..., :3] * 255).astype(np.uint8)


def _png_rgb(rgb: np.ndarray, zoom: int = 1, boxes=()) -> bytes:
    """PNG of an RGB array enlarged by ``zoom`` (nearest) with rectangles drawn on it;
    ``boxes``: ((row0, row1, col0, col1), colour) in source pixels, half-open."""
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


def _image_frames(nc: Path, band: str):
    """(list of PNG data URIs per slider hour, colour-bar PNG, caption) of one series."""
    import xarray as xr

    from imaging.metrics import background_window
    from imaging.radiometry import brightness_temperature

    with xr.open_dataset(nc, engine="h5netcdf") as ds:
        rad = ds["radiance"].values
        cov = ds["coverage"].values
        th = ds["time"].values.astype(float)
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
    ks = [_nearest(th, hr) for hr in SLIDER_HOURS]
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
    second = (lambda L: float(brightness_temperature(L, band)),
              "apparent temperature at the aperture [K]")
    bar = _colourbar_png(float(vmin), float(vmax), f"at-aperture radiance {band} µm "
                         "[W m-2 sr-1]", second=second)
    cap = (f"{h * res / 1000:.1f} km × {w * res / 1000:.1f} km around the ship "
           f"({res:g} m pixels); cyan: ship pixels (target), white: local background window "
           "of the SCR")
    return uris, bar, cap


def _surface_frames(case_dir: Path, title: str):
    """(PNG data URIs per slider hour, caption) of the ship coloured by its surface
    temperature, one colour scale over the day (a weather record's first day)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.collections import PolyCollection

    hist = load_history(case_dir)
    v, f = hist.vertices, hist.faces
    th = hist.times_s / 3600.0
    ks = [_nearest(th % 24.0 if th[-1] > 24.0 + 1e-9 else th, hr) for hr in SLIDER_HOURS]
    # only the rows shown (a record's are read from its file)
    temp = {k: np.asarray(hist.face_temperature[k], dtype=float) for k in set(ks)}
    vmin, vmax = np.nanpercentile(np.stack([temp[k] for k in ks]), [0.5, 99.5])
    from ..geometry.surface_maps import OBLIQUE_VIEW_DEG, project

    u, w, depth = project(v, *OBLIQUE_VIEW_DEG)
    order = np.argsort(depth[f].mean(axis=1))           # far faces first (painter's order)
    polys = np.stack([u[f], w[f]], axis=-1)[order]
    fig, ax = plt.subplots(figsize=(5.2, 2.6), dpi=80)
    coll = PolyCollection(polys, cmap="inferno", edgecolors="none", antialiaseds=False)
    coll.set_clim(vmin, vmax)
    ax.add_collection(coll)
    ax.set_xlim(u.min() - 1, u.max() + 1)
    ax.set_ylim(w.min() - 1, w.max() + 1)
    ax.set_aspect("equal")
    ax.axis("off")
    cb = fig.colorbar(coll, ax=ax, shrink=0.8, pad=0.01)
    cb.set_label("outer-surface temperature [K]", fontsize=7)
    cb.ax.tick_params(labelsize=6)
    ttl = ax.set_title("", fontsize=8)
    uris = []
    for hr, k in zip(SLIDER_HOURS, ks):
        coll.set_array(temp[k][order])
        ttl.set_text(f"{title}, {_hhmm(th[k] % 24 if th[k] < 24 - 1e-9 else th[k])} local")
        buf = io.BytesIO()
        fig.savefig(buf, format="png")
        uris.append(_b64png(buf.getvalue()))
    plt.close(fig)
    return uris, (f"one colour scale for the whole day ({vmin:.1f}–{vmax:.1f} K); oblique view "
                  "from the starboard quarter, bow to the right")


def _scr_svg(m: pd.DataFrame, crossovers: list[float], label: str) -> str:
    """Inline SVG of the SCR over the day (log scale) with a cursor line the script moves."""
    W, H, L, R, T, B = 560, 170, 46, 10, 18, 26
    t = m["time_h"].to_numpy(float)
    scr = np.clip(m["scr"].to_numpy(float), 1e-3, None)
    finite = scr[np.isfinite(scr)]
    if not finite.size:
        finite = np.array([1.0])
    lo = np.floor(np.log10(max(np.min(finite), 1e-3)))
    hi = np.ceil(np.log10(max(np.max(finite), 10 ** (lo + 1))))
    sx = (W - L - R) / max(24.0, float(np.nanmax(t)) if t.size else 24.0)

    def X(h):
        return L + h * sx

    def Y(s):
        return T + (hi - np.log10(s)) / (hi - lo) * (H - T - B)

    pts = " ".join(f"{X(a):.1f},{Y(b):.1f}" for a, b in zip(t, scr) if np.isfinite(b))
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
        g.append(f'<line x1="{L}" x2="{W - R}" y1="{y:.1f}" y2="{y:.1f}" stroke="#bc4c00" '
                 'stroke-dasharray="4 3"/>')
    for h in range(0, 25, 3):
        g.append(f'<text x="{X(h):.1f}" y="{H - 12}" font-size="9" text-anchor="middle">'
                 f"{h:02d}</text>")
    g.append(f'<text x="{(L + W - R) / 2}" y="{H - 1}" font-size="9" text-anchor="middle">'
             "local time [h]; SCR [-] (log scale); orange dashed: SCR = 1; grey: crossovers"
             "</text>")
    for c in crossovers:
        g.append(f'<line x1="{X(c):.1f}" x2="{X(c):.1f}" y1="{T}" y2="{H - B}" '
                 'stroke="#888" stroke-dasharray="2 2"/>')
    g.append(f'<polyline fill="none" stroke="#0969da" stroke-width="1.5" points="{pts}"/>')
    vals = [float(scr[_nearest(t, hr)]) for hr in SLIDER_HOURS]
    g.append(f'<line class="cursor" data-x0="{L}" data-dx="{sx:.4f}" x1="{L}" x2="{L}" '
             f'y1="{T}" y2="{H - B}" stroke="#cf222e" stroke-width="2"/>')
    g.append(f'<text class="cursor-value" data-values="{html.escape(json.dumps(vals))}" '
             f'x="{W - R}" y="12" font-size="11" text-anchor="end" fill="#cf222e"></text>')
    g.append("</svg>")
    return "".join(g)


def _frame_group(uris: list[str], alt: str) -> str:
    return "".join(f'<img data-frame="{i}" alt="{html.escape(alt)} {_hhmm(h)}" src="{u}"'
                   + ("" if i == 0 else " hidden") + ">"
                   for i, (h, u) in enumerate(zip(SLIDER_HOURS, uris)))


def day_section(run: Path) -> str:
    """The slider section (HTML), or "" when the run has neither images nor a history."""
    blocks = []
    imaging = run / "imaging"
    if imaging.is_dir():
        cross = pd.DataFrame()
        if (imaging / "crossovers.csv").is_file():
            cross = pd.read_csv(imaging / "crossovers.csv")
        for season, band, f in _series_files(imaging):
            m = pd.read_csv(f)
            cx = []
            if len(cross):
                sel = cross[(cross["season"] == season) & (cross["band"].astype(str) == band)]
                cx = list(sel["time_h"].astype(float))
            fig = []
            nc = imaging / f"images_{season}_{band}.nc"
            if nc.is_file():
                uris, bar, cap = _image_frames(nc, band)
                fig.append(f'<figure class="frames">{_frame_group(uris, f"{season} {band} um")}'
                           f'<img alt="colour bar {season} {band} um" src="{_b64png(bar)}">'
                           f"<figcaption>{html.escape(cap)}; one colour scale for the whole "
                           "day</figcaption></figure>")
            fig.append(_scr_svg(m, cx, f"{season}, {band} µm: local SCR"))
            blocks.append(f"<h3>{html.escape(season)}, {html.escape(band)} µm</h3>"
                          f'<div class="row">{"".join(fig)}</div>')
    thermal = run / "thermal"
    if thermal.is_dir():
        for d in sorted(p for p in thermal.iterdir() if p.is_dir()):
            if history_file(d).is_file():
                uris, cap = _surface_frames(d, d.name)
                blocks.append(f"<h3>{html.escape(d.name)}: ship surface temperature</h3>"
                              f'<figure class="frames">{_frame_group(uris, d.name)}'
                              f"<figcaption>{html.escape(cap)}</figcaption></figure>")
    if not blocks:
        return ""
    labels = json.dumps([_hhmm(h) for h in SLIDER_HOURS])
    control = (f'<div class="slider"><button type="button" id="day-play">play</button> '
               f'<input type="range" id="day-slider" min="0" max="{len(SLIDER_HOURS) - 1}" '
               f'step="1" value="12" aria-label="local time" data-labels="{html.escape(labels)}">'
               ' <output id="day-time">12:00</output> local</div>')
    return control + "".join(blocks)


#: The report's only script: moves every frame group, SCR cursor and label to the slider's
#: hour; the play button steps through the day.
SCRIPT = """
(function(){
var s=document.getElementById('day-slider');if(!s)return;
var labels=JSON.parse(s.getAttribute('data-labels')),out=document.getElementById('day-time');
function show(i){
 out.textContent=labels[i];
 document.querySelectorAll('img[data-frame]').forEach(function(e){
  e.hidden=(+e.getAttribute('data-frame'))!==i;});
 document.querySelectorAll('line.cursor').forEach(function(l){
  var x=(+l.getAttribute('data-x0'))+i*(+l.getAttribute('data-dx'));
  l.setAttribute('x1',x);l.setAttribute('x2',x);});
 document.querySelectorAll('text.cursor-value').forEach(function(t){
  var v=JSON.parse(t.getAttribute('data-values'))[i];
  t.textContent=labels[i]+'  SCR '+(v<10?v.toPrecision(2):v.toFixed(0));});
 document.body.setAttribute('data-shown',labels[i]);
}
s.addEventListener('input',function(){show(+s.value);});
var timer=null,btn=document.getElementById('day-play');
btn.addEventListener('click',function(){
 if(timer){clearInterval(timer);timer=null;btn.textContent='play';return;}
 btn.textContent='pause';
 timer=setInterval(function(){s.value=(+s.value+1)%labels.length;show(+s.value);},700);});
show(+s.value);
})();
"""
