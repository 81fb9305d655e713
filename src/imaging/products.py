"""Products of the imaging experiment: NetCDF/GeoTIFF radiance, PNG panels and curves, CSV.

Every file is written under a temporary name in the output directory and moved into place
once complete (:mod:`shipthermal.atomic`), so an interrupted run leaves no half-written file.
Rasters are float32 in physical units (W m-2 sr-1); the NetCDF stacks follow CF (time with
its zone, a grid mapping), GeoTIFF bands carry their unit and instant, CSV headers their
units (docs/DATA.md).
"""

from __future__ import annotations

import json
import os

import numpy as np
import pandas as pd

from shipthermal.atomic import atomic_path
from shipthermal.errors import require
from shipthermal.figures import (OKABE_ITO, FigureOptions, add_scale_bar, band_label,
                                 save_figure, unit_label)
from shipthermal.optics.planck import band_radiance, brightness_temperature
from shipthermal.units import (HOUR, clock_offset_hours, clock_origin, utc_offset_text,
                               with_units, zone_text)

from . import cf
from .instruments import band_product, product_brightness_temperature, product_radiance
from .metrics import background_window
from .scene import as_scene_background

__all__ = ["write_products", "write_series_netcdf", "write_typical_geotiff", "plot_panels",
           "plot_scr_curves"]


#: The radiance unit as figures print it
R_UNIT = unit_label("W m-2 sr-1")


def _csv(df: pd.DataFrame, path: str, clock: str | None = None) -> str:
    """Write a table atomically with units in its headers (``name [unit]``; local clock
    columns with the zone ``clock``: :func:`shipthermal.units.with_units`)."""
    with atomic_path(path) as tmp:
        with_units(df, clock=clock).to_csv(tmp, index=False, float_format="%.7g")
    return path


def _savefig(fig, path: str, figures: FigureOptions | None = None) -> str:
    return os.fspath(save_figure(fig, path, figures))


def _ship_marker(ax, box, h, res_km, label: bool = True) -> None:
    """A ship marker (triangle, labelled) at the centre of the half-open pixel box."""
    r0, r1, c0, c1 = box
    x, y = 0.5 * (c0 + c1) * res_km, (h - 0.5 * (r0 + r1)) * res_km
    ax.plot([x], [y], marker="v", ms=6, mfc="white", mec="black", mew=0.8, ls="none")
    if label:
        ax.annotate("ship", (x, y), xytext=(0, 6), textcoords="offset points", ha="center",
                    fontsize=6, color="black",
                    bbox={"boxstyle": "round,pad=0.15", "fc": "white", "ec": "none",
                          "alpha": 0.8})


def _hhmm(hours: float) -> str:
    m = int(round(hours * 60.0))
    return f"{(m // 60) % 24:02d}:{m % 60:02d}"


def _utc_instants(date: str, time_zone: str, times_s) -> np.ndarray:
    """datetime64 [ns] UTC (naive) of ``times_s`` [s after local midnight of ``date``]."""
    origin = pd.Timestamp(clock_origin(date, time_zone)).tz_convert("UTC").tz_localize(None)
    return (origin + pd.to_timedelta(np.asarray(times_s, float), unit="s")).to_numpy()


def write_series_netcdf(path, sr, grid, attrs: dict | None = None, *, date: str | None = None,
                        time_zone: str | None = None) -> str:
    """Write one season/band image series as NetCDF in the CF conventions (h5netcdf),
    atomically.

    Variables ``radiance`` and ``leaving_radiance`` (time, y, x) float32 [W m-2 sr-1] on the
    stored crop, the sensor products ``spectral_radiance`` (band-mean, [W m-2 sr-1 um-1])
    and ``brightness_temperature`` [K] as the band's instrument defines them
    (:func:`imaging.instruments.product_brightness_temperature`: Landsat's K1/K2, else the
    band's Planck integral inverted), ``coverage`` (y, x) float32 [1]; coordinates ``time`` (CF units counted from
    local midnight of ``date`` with the zone's UTC offset, e.g. ``seconds since 2023-07-15
    00:00:00+08:00``: xarray decodes it to UTC datetimes), ``time_local_h`` (the same instants
    as hours after that local midnight [h]), ``x``, ``y`` (map coordinates of pixel centres
    [m]); the CRS in the grid mapping variable ``spatial_ref`` (CF parameters, ``crs_wkt``,
    GDAL's ``spatial_ref`` and ``GeoTransform``) that every data variable names, so
    GDAL, QGIS and rioxarray (``xr.open_dataset(path, decode_coords="all")``) georeference
    it. ``date``/``time_zone`` (IANA) default to
    ``attrs["date"]``/``attrs["timezone"]``.
    """
    # deferred: xarray takes 0.14 s to import (measured), needed only for the NetCDF
    import xarray as xr

    attrs = dict(attrs or {})
    date = date or attrs.get("date")
    time_zone = time_zone or attrs.get("timezone")
    require(bool(date) and bool(time_zone), "date/time_zone", (date, time_zone),
            "the local date and IANA zone of the run's clock are needed for CF time units")
    x, y = cf.pixel_centres(grid.transform, sr.crop)
    r0, r1, c0, c1 = sr.crop
    mapping = cf.grid_mapping_attrs(grid.crs)
    gm = {"grid_mapping": cf.GRID_MAPPING} if mapping else {}
    hours = np.asarray(sr.stack_times_s, float) / HOUR
    t_attrs, t_enc = cf.time_attrs(date, time_zone)
    band = band_label(sr.band)
    data = {
        "radiance": (("time", "y", "x"), sr.radiance,
                     {"units": "W m-2 sr-1", **gm,
                      "long_name": f"at-aperture band radiance {band} (paper eq. 1)"}),
        "leaving_radiance": (("time", "y", "x"), sr.leaving,
                             {"units": "W m-2 sr-1", **gm,
                              "long_name": f"surface-leaving band radiance {band}, "
                                           "area-mixed (eq. 2)"}),
        "spectral_radiance": (("time", "y", "x"),
                              product_radiance(sr.radiance, band_product(sr.band)).astype(
                                  np.float32),
                              {"units": "W m-2 sr-1 um-1", **gm,
                               "long_name": f"band-mean spectral radiance {band} "
                                            "(sensor product)"}),
        "brightness_temperature": (("time", "y", "x"), product_brightness_temperature(
            sr.radiance, band_product(sr.band)).astype(np.float32),
            {"units": "K", **gm, "long_name": f"at-aperture brightness temperature {band} "
                                             "(sensor product definition)"}),
        "coverage": (("y", "x"), sr.coverage[r0:r1, c0:c1],
                     {"units": "1", **gm, "long_name": "ship area fraction of the pixel"})}
    if mapping:         # CF: named by ``grid_mapping``, not an auxiliary coordinate
        data[cf.GRID_MAPPING] = ((), np.int32(0), {**mapping, "GeoTransform":
                                                   cf.geotransform(grid.transform, sr.crop)})
    ds = xr.Dataset(
        data,
        coords={"time": ("time", _utc_instants(date, time_zone, sr.stack_times_s), t_attrs),
                "time_local_h": ("time", hours,
                                 {"units": "h", "long_name": f"hours after local midnight of "
                                  f"{date} ({zone_text(date, time_zone)})"}),
                "x": ("x", x, cf.map_axis_attrs("x", grid.crs)),
                "y": ("y", y, cf.map_axis_attrs("y", grid.crs))},
        attrs={"Conventions": cf.CONVENTIONS,
               "title": f"Ship in port, {sr.season}, {band}", "season": sr.season,
               "band_um": sr.band, "crop_rows_cols": list(sr.crop),
               "local_time_zone": zone_text(date, time_zone),
               "source": "shipthermal imaging (ray-traced scene, band radiance)",
               **{k: v for k, v in attrs.items() if k != "timezone"},
               "timezone": time_zone})
    enc = {v: {"zlib": True, "complevel": 4} for v in ("radiance", "leaving_radiance",
                                                       "spectral_radiance",
                                                       "brightness_temperature", "coverage")}
    enc["time"] = t_enc
    with atomic_path(path) as tmp:
        ds.to_netcdf(tmp, engine="h5netcdf", encoding=enc)
    return path


def write_typical_geotiff(path, sr, grid, background: str = "", *, date: str | None = None,
                          time_zone: str | None = None) -> str | None:
    """Full-scene float32 GeoTIFF of the kept frames (one band per time) [W m-2 sr-1].

    Every band has the unit ``W m-2 sr-1`` (GDAL's band unit), a description naming the
    time with its zone and the background (``background``), and its instant as metadata
    (``time_utc``, ``time_local`` with the UTC offset, ``hours_after_local_midnight``); the
    file's metadata names the band, the quantity and the zone. ``date``/``time_zone``: the
    run's clock (local midnight of ``date`` in the IANA zone); without them the times are
    given as hours after local midnight only.
    """
    # deferred: the background package loads scikit-learn, pykrige and scipy.stats (1.5 s
    # over the experiment's imports, measured); only the GeoTIFF writer needs it
    from .background.outputs import time_tags, write_geotiff

    if not sr.frames:
        return None
    keys = sorted(sr.frames)
    data = np.stack([sr.frames[k].radiance for k in keys]).astype(np.float32)
    what = f"; {background}" if background else ""
    zone = zone_text(date, time_zone) if date and time_zone else "local"
    desc = [f"at-aperture radiance {band_label(sr.band)} [W m-2 sr-1] at {_hhmm(k / HOUR)} "
            f"{zone}{what}" for k in keys]
    tags = (time_tags(clock_origin(date, time_zone), keys) if date and time_zone else
            [{"hours_after_local_midnight": f"{k / HOUR:.6g}"} for k in keys])
    meta = {"quantity": "at-aperture band radiance", "band_um": sr.band, "season": sr.season,
            "local_time_zone": zone, "background": background}
    return write_geotiff(os.fspath(path), data, grid, descriptions=desc, units="W m-2 sr-1",
                         band_tags=tags, tags=meta)


def _display_box(coverage, size, shape):
    rows = np.flatnonzero(coverage.any(axis=1))
    cols = np.flatnonzero(coverage.any(axis=0))
    rc, cc = (rows[0] + rows[-1] + 1) // 2, (cols[0] + cols[-1] + 1) // 2
    h, w = min(size, shape[0]), min(size, shape[1])
    r0 = int(np.clip(rc - h // 2, 0, shape[0] - h))
    c0 = int(np.clip(cc - w // 2, 0, shape[1] - w))
    return r0, r0 + h, c0, c0 + w


def _rect(ax, box, h, res_km, **kw):
    """Draw the half-open pixel box ``(row0, row1, col0, col1)`` of a crop ``h`` rows high
    on axes whose extent is in km with the origin at the crop's lower-left corner."""
    # imported on use: matplotlib takes about a second to load
    from matplotlib.patches import Rectangle

    r0, r1, c0, c1 = box
    ax.add_patch(Rectangle((c0 * res_km, (h - r1) * res_km), (c1 - c0) * res_km,
                           (r1 - r0) * res_km, fill=False, **kw))


def plot_panels(path, series: dict, band: str, typical: dict, display_px: int = 40,
                backgrounds: dict | None = None, shared_scale: bool = True,
                labelled: dict | None = None, figures: FigureOptions | None = None) -> str:
    """Image panels at the typical times, one row per season (like the paper's Figs. 14/16).

    Each panel is the at-aperture radiance [W m-2 sr-1] of a ``display_px`` square around the
    ship, both axes in km from the crop's south-west corner; the title gives the time, the
    signed contrast and the local SCR. The ship's pixels (target) and the SCR's local
    background window (:func:`imaging.metrics.background_window`) are outlined.

    ``shared_scale`` (default): one colour scale per season row, shared by all its times (1st
    to 99.5th percentile of the row), on one colour bar with the radiance units and the
    apparent (brightness) temperature at the aperture as a second scale; False: one scale
    per panel. ``backgrounds`` (``{season: GriddedBackground}``): a first column shows the
    crop's background classes with a legend and a ship marker, and the pixel size comes
    from it (else 30 m). Every map has a scale bar. ``figures``: resolution and vector
    copies (:class:`shipthermal.figures.FigureOptions`).
    """
    # imported on use: matplotlib takes about a second to load
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    backgrounds = backgrounds or {}
    seasons = [s for s in ("summer", "winter") if (s, band) in series] + sorted(
        {s for s, b in series if b == band and s not in ("summer", "winter")})
    ntime = max(1, max(len(typical.get(s, ())) for s in seasons))
    with_classes = any(s in backgrounds for s in seasons)
    lead = 1 if with_classes else 0
    ncol = ntime + lead
    fig, axes = plt.subplots(len(seasons), ncol, figsize=(2.5 * ncol + 1.2, 2.75 * len(seasons)),
                             squeeze=False, constrained_layout=True)
    for i, season in enumerate(seasons):
        _panel_row(fig, axes[i], series[(season, band)], backgrounds.get(season), season, band,
                   typical.get(season, ()), display_px, ntime, with_classes, shared_scale)
    synthetic = any("synthetic port" in background_label(b) for b in
                    (labelled or backgrounds).values())
    fig.suptitle(("Ship in a synthetic port (not a real place)" if synthetic else "Ship in port")
                 + f", at-aperture radiance {band_label(band)}; "
                 + ("one colour scale per season for all times" if shared_scale
                    else "one colour scale per panel")
                 + "\ncyan: ship pixels, white dashed: local SCR background window; "
                   f"C: target − background contrast [{R_UNIT}]", fontsize=8)
    out = _savefig(fig, os.fspath(path), figures)
    plt.close(fig)
    return out


def _panel_row(fig, row_axes, sr, bg, season: str, band: str, typical_hours, display_px: int,
               ntime: int, with_classes: bool, shared_scale: bool) -> None:
    """One season's row of :func:`plot_panels`: the background classes (when shown), the
    radiance at each typical time on the same crop, the row's colour bar."""
    lead = 1 if with_classes else 0
    res = float(bg.resolution_m) if bg is not None else 30.0
    res_km = res / 1000.0
    hours = [h for h in typical_hours if float(h) * HOUR in sr.frames]
    if not hours:
        for ax in row_axes:
            ax.axis("off")
        return
    first = sr.frames[float(hours[0]) * HOUR]
    mask = first.coverage > 0
    r0, r1, c0, c1 = _display_box(mask, display_px, first.radiance.shape)
    h, w = r1 - r0, c1 - c0
    ext = [0, w * res_km, 0, h * res_km]
    rows, cols = np.flatnonzero(mask.any(axis=1)), np.flatnonzero(mask.any(axis=0))
    target = (rows[0] - r0, rows[-1] + 1 - r0, cols[0] - c0, cols[-1] + 1 - c0)
    wr0, wr1, wc0, wc1 = background_window(mask)
    window = (wr0 - r0, wr1 - r0, wc0 - c0, wc1 - c0)
    imgs = [sr.frames[float(hr) * HOUR].radiance[r0:r1, c0:c1] for hr in hours]
    row_lim = np.percentile(np.stack(imgs), [1, 99.5])
    if with_classes:
        ax = row_axes[0]
        if bg is not None:
            _classes_panel(ax, np.asarray(bg.class_map)[r0:r1, c0:c1], target, h, w, res_km,
                           ext, season)
        else:
            ax.axis("off")
    im = None
    for j in range(ntime):
        ax = row_axes[lead + j]
        if j >= len(hours):
            ax.axis("off")
            continue
        img = imgs[j]
        vmin, vmax = row_lim if shared_scale else np.percentile(img, [1, 99.5])
        im = ax.imshow(img, cmap="inferno", vmin=vmin, vmax=vmax, extent=ext,
                       interpolation="nearest")
        _rect(ax, target, h, res_km, ec="cyan", lw=0.9)
        _rect(ax, window, h, res_km, ec="white", lw=0.8, ls="--")
        add_scale_bar(ax, w * res_km)
        k = int(np.argmin(np.abs(sr.times_s - float(hours[j]) * HOUR)))
        con = sr.metrics["contrast"].iloc[k]
        scr = sr.metrics["scr"].iloc[k]
        ax.set_title(f"{season} {_hhmm(hours[j])}\nC={con:+.3g}, SCR={scr:.2g}", fontsize=8)
        ax.tick_params(labelsize=6)
        ax.set_xlabel("km east", fontsize=7)
        if j == 0 and not with_classes:
            ax.set_ylabel("km north", fontsize=7)
        if not shared_scale:
            cb = fig.colorbar(im, ax=ax, shrink=0.8)
            cb.ax.tick_params(labelsize=6)
            cb.set_label(R_UNIT, fontsize=6)
    if shared_scale and im is not None:
        _row_colour_bar(fig, list(row_axes[lead:]), im, band, row_lim)


def _classes_panel(ax, cm, target, h: int, w: int, res_km: float, ext, season: str) -> None:
    """The crop's background classes with a legend, the ship's outline and marker."""
    # deferred: matplotlib takes about a second to load, the background package 1.5 s over
    # the experiment's imports (measured); only the classes panel needs them
    from matplotlib.colors import ListedColormap
    from matplotlib.patches import Patch

    from .background.classify import CLASS_COLOURS, CLASS_NAMES

    codes = sorted(CLASS_NAMES)
    ax.imshow(cm, cmap=ListedColormap([CLASS_COLOURS[c] for c in codes]),
              vmin=codes[0] - 0.5, vmax=codes[-1] + 0.5, extent=ext,
              interpolation="nearest")
    _rect(ax, target, h, res_km, ec="k", lw=1.0)
    _ship_marker(ax, target, h, res_km)
    add_scale_bar(ax, w * res_km, colour="black")
    present = [c for c in codes if (cm == c).any()]
    ax.legend(handles=[Patch(color=CLASS_COLOURS[c], label=CLASS_NAMES[c])
                       for c in present] + [Patch(fill=False, ec="k", label="ship")],
              fontsize=6, loc="upper left", framealpha=0.85)
    ax.set_title(f"{season}: background classes", fontsize=8)
    ax.set_xlabel("km east", fontsize=7)
    ax.set_ylabel("km north", fontsize=7)
    ax.tick_params(labelsize=6)


def _row_colour_bar(fig, axes: list, im, band: str, row_lim) -> None:
    """One colour bar for a row's radiance panels, with the apparent temperature at the
    aperture as a second scale where the row's radiances are positive."""
    cb = fig.colorbar(im, ax=axes, shrink=0.9, pad=0.02)
    cb.set_label(f"radiance {band_label(band)} [{R_UNIT}]", fontsize=7)
    cb.ax.tick_params(labelsize=6)
    if row_lim[0] > 0:
        def to_t(L):
            return brightness_temperature(np.maximum(L, 1e-6), band)

        def to_l(T):
            with np.errstate(over="ignore"):
                return band_radiance(np.maximum(T, 100.0), band)

        tb = cb.ax.secondary_yaxis("left", functions=(to_t, to_l))
        tb.set_ylabel("apparent temperature [K]", fontsize=7)
        tb.tick_params(labelsize=6)


def plot_scr_curves(path, series: dict, band: str, labels: dict | None = None,
                    figures: FigureOptions | None = None) -> str:
    """Local SCR (eq. 22, log scale, SCR = 1 marked) and signed contrast over the day per
    season (like Figs. 15/17); solid black SCR, dashed vermillion contrast."""
    # imported on use: matplotlib takes about a second to load
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    seasons = [s for s, b in series if b == band]
    fig, axes = plt.subplots(len(seasons), 1, figsize=(8, 3.0 * len(seasons)), squeeze=False,
                             constrained_layout=True)
    for ax, season in zip(axes[:, 0], seasons):
        sr = series[(season, band)]
        m = sr.metrics
        scr_c, con_c = OKABE_ITO["black"], OKABE_ITO["vermillion"]
        ax.plot(m["time_h"], np.clip(m["scr"], 1e-3, None), color=scr_c, lw=1.5,
                label="local SCR (eq. 22)")
        ax.set_yscale("log")
        ax.axhline(1.0, color=scr_c, lw=0.8, ls=(0, (1, 2)))
        ax.text(0.0, 1.0, " SCR = 1", fontsize=7, va="bottom", color=scr_c)
        ax.set_ylabel("SCR [-] (log scale)", color=scr_c)
        span_h = max(24.0, float(sr.times_s[-1]) / HOUR)
        ax.set_xlim(0, span_h)
        if span_h <= 24.0:
            ax.set_xticks(range(0, 25, 2))
        else:                                     # a weather record: one tick per day
            ax.set_xticks(np.arange(0.0, span_h + 1e-9, 24.0 * max(1, round(span_h / 24 / 15))))
        many = len(sr.crossovers) > 12            # a record: lines without labels
        ax2 = ax.twinx()
        ax2.plot(m["time_h"], m["contrast"], color=con_c, lw=1.0, ls="--", label="contrast")
        ax2.axhline(0.0, color=con_c, lw=0.5, ls=":")
        ax2.set_ylabel(f"contrast [{R_UNIT}]", color=con_c)
        for c in sr.crossovers:
            ax.axvline(c.time / HOUR, color="0.45", ls="-", lw=0.4 if many else 0.8)
            if not many:
                ax.text(c.time / HOUR, ax.get_ylim()[1], f" {_hhmm(c.time / HOUR)}",
                        fontsize=7, va="top")
        bg = (labels or {}).get(season, "")
        ax.set_title(f"({'ab'[seasons.index(season)] if len(seasons) <= 2 else season}) "
                     f"{season}, {band_label(band)}; thin grey: thermal crossover"
                     + (f"\nbackground: {bg.split(';')[0]}" if bg else ""), fontsize=9)
        ax.set_xlabel("local time [h]" if span_h <= 24.0 else
                      "hours after local midnight of the first day [h]")
    out = _savefig(fig, os.fspath(path), figures)
    plt.close(fig)
    return out


def background_label(background) -> str:
    """What a background is, in the words every product uses: the physical model's own
    label (a synthetic port or the scene it is anchored on), or the paper's chain on the
    synthetic port or on real files."""
    src = getattr(background, "source", None) or background
    label = getattr(src, "label", "")
    if label:
        return f"{label}; physical model driven by the scenario's weather"
    if getattr(src, "synthetic_truth", None) is not None:
        return ("synthetic port (not a real place) with a generated Landsat scene and met grid "
                "of the built-in design day; the paper's chain")
    if hasattr(src, "overpass_utc"):
        return f"Landsat scene of {src.overpass_utc:%Y-%m-%d %H:%M} UTC; the paper's chain"
    return "user background"


def _with_utc(metrics: pd.DataFrame, scen) -> pd.DataFrame:
    """The metrics with the instant of every frame in UTC (ISO 8601) after ``time_h``."""
    m = metrics.copy()
    utc = pd.DatetimeIndex(_utc_instants(scen.date, scen.tz, m["time_s"]))
    m.insert(int(m.columns.get_loc("time_h")) + 1, "time_utc", utc.strftime("%Y-%m-%dT%H:%M:%SZ"))
    return m


def _clock_of(scenarios: dict) -> str:
    """The local clock's zone of the scenarios (``"UTC+8"``; several: joined by ``/``)."""
    zones = dict.fromkeys(utc_offset_text(clock_offset_hours(s.date, s.tz))
                          for s in scenarios.values())
    return "/".join(zones)


def write_products(out_dir, series, crossovers, comparison, scenarios, histories, typical,
                   shared_panel_scale: bool = True, figures: FigureOptions | None = None) -> dict:
    """Write every product of :func:`imaging.experiment.run_experiment`; returns the paths.
    ``figures``: resolution and vector copies of the figures."""
    files = {}
    p = lambda name: os.path.join(out_dir, name)  # noqa: E731
    bands = sorted({b for _, b in series})
    for (season, band), sr in series.items():
        scen = scenarios[season]
        grid = as_scene_background(scen.background).grid
        hist = histories[season]
        attrs = {"ship_temperatures": hist.label or "user history",
                 "view_zenith_deg": scen.view_zenith_deg,
                 "view_azimuth_deg": scen.view_azimuth_deg,
                 "samples_per_pixel": scen.samples_per_pixel,
                 "atmosphere_backend": scen.atmosphere_backend, "date": scen.date,
                 "timezone": scen.tz, "background": background_label(scen.background)}
        tag = f"{season}_{band}"
        files[f"netcdf_{tag}"] = write_series_netcdf(p(f"images_{tag}.nc"), sr, grid, attrs)
        tif = write_typical_geotiff(p(f"typical_{tag}.tif"), sr, grid,
                                    background_label(scen.background), date=scen.date,
                                    time_zone=scen.tz)
        if tif:
            files[f"geotiff_{tag}"] = tif
        files[f"metrics_{tag}"] = _csv(_with_utc(sr.metrics, scen), p(f"metrics_{tag}.csv"))
    for band in bands:
        backgrounds = {s: as_scene_background(scenarios[s].background) for s, b in series
                       if b == band}
        files[f"panels_{band}"] = plot_panels(p(f"panels_{band}.png"), series, band, typical,
                                              backgrounds=backgrounds,
                                              shared_scale=shared_panel_scale,
                                              labelled={s: scenarios[s].background
                                                        for s in backgrounds},
                                              figures=figures)
        files[f"scr_{band}"] = plot_scr_curves(
            p(f"scr_{band}.png"), series, band,
            labels={s: background_label(scenarios[s].background) for s, b in series if b == band},
            figures=figures)
    clock = _clock_of(scenarios)
    files["crossovers"] = _csv(crossovers, p("crossovers.csv"), clock)
    files["band_comparison"] = _csv(comparison, p("band_comparison.csv"), clock)
    summary = {
        "ship_temperatures": {s: h.label for s, h in histories.items()},
        "scenarios": {s: {"date": sc.date, "latitude": sc.latitude, "longitude": sc.longitude,
                          "tz": sc.tz, "wind_speed": sc.wind_speed,
                          "aerosol": sc.atmosphere_aerosol,
                          "view_zenith_deg": sc.view_zenith_deg,
                          "view_azimuth_deg": sc.view_azimuth_deg,
                          "samples_per_pixel": sc.samples_per_pixel,
                          "background": background_label(sc.background),
                          "placement": next((vars(sr.placement) for (ss, _), sr in series.items()
                                             if ss == s and sr.placement is not None), None)}
                      for s, sc in scenarios.items()},
        "crossovers": crossovers.to_dict(orient="records"),
        "band_comparison": comparison.to_dict(orient="records"),
        "rays": {f"{s}_{b}": sr.rays for (s, b), sr in series.items()},
    }
    with atomic_path(p("summary.json")) as tmp, open(tmp, "w", encoding="utf-8") as fh:
        json.dump(summary, fh, indent=2, default=str)
    files["summary"] = p("summary.json")
    return files
