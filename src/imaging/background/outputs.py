"""Products of the background: GeoTIFFs (float32 K), class map, PNGs, CSV tables.

Every file is written under a temporary name and moved into place
(:mod:`shipthermal.atomic`), and only after the whole chain has succeeded, so a failed run
leaves nothing half-written.
"""

from __future__ import annotations

import datetime
import json
import os

import numpy as np
import pandas as pd
import rasterio

from shipthermal.atomic import atomic_path
from shipthermal.figures import FigureOptions, add_scale_bar, save_figure
from shipthermal.units import utc_offset_text, with_units

from .classify import CLASS_CODES, CLASS_COLOURS, CLASS_NAMES, format_jm_table
from .landsat.bands import MASK_BITS

__all__ = ["write_outputs", "write_overpass_outputs", "write_geotiff", "write_physical_outputs",
           "time_tags"]


def write_geotiff(path, data, grid, nodata=None, descriptions=None, colormap=None,
                  units=None, band_tags=None, tags=None) -> str:
    """Write a (bands, rows, cols) or (rows, cols) array as a GeoTIFF on ``grid`` atomically.

    Parameters
    ----------
    descriptions : list of str, optional
        One description per band (GDAL's band description, QGIS's band name).
    units : str or list of str, optional
        The unit of every band (one string) or of each band (UDUNITS spelling, e.g.
        ``"K"``, ``"W m-2 sr-1"``): GDAL's band unit type, shown by ``gdalinfo`` and QGIS.
    band_tags : list of dict, optional
        Metadata of each band (e.g. its time as ``time_utc``, ``time_local``).
    tags : dict, optional
        Metadata of the file.
    """
    arr = data if data.ndim == 3 else data[None]
    with atomic_path(path) as tmp, rasterio.open(
            tmp, "w", driver="GTiff", height=arr.shape[1], width=arr.shape[2], count=arr.shape[0],
            dtype=arr.dtype, crs=grid.crs, transform=grid.transform, nodata=nodata,
            compress="deflate") as dst:
        dst.write(arr)
        if descriptions:
            for k, d in enumerate(descriptions, start=1):
                dst.set_band_description(k, d)
        if units:
            each = [units] * arr.shape[0] if isinstance(units, str) else list(units)
            for k, u in enumerate(each, start=1):
                dst.set_band_unit(k, u)
        for k, t in enumerate(band_tags or (), start=1):
            dst.update_tags(k, **{key: str(v) for key, v in t.items()})
        if tags:
            dst.update_tags(**{key: str(v) for key, v in tags.items()})
        if colormap:
            dst.write_colormap(1, colormap)
    return path


def time_tags(origin, times_s) -> list[dict]:
    """Band metadata of instants ``times_s`` [s after ``origin``, an aware datetime: local
    midnight of the run's first day, :func:`shipthermal.units.clock_origin`]: ``time_utc``
    and ``time_local`` (ISO 8601, the latter with its UTC offset) and
    ``hours_after_local_midnight`` [h]."""
    out = []
    for t in np.asarray(times_s, float):
        utc = (origin + datetime.timedelta(seconds=float(t))).astimezone(datetime.timezone.utc)
        local = utc.astimezone(origin.tzinfo)
        out.append({"time_utc": utc.strftime("%Y-%m-%dT%H:%M:%SZ"),
                    "time_local": local.isoformat(timespec="seconds"),
                    "hours_after_local_midnight": f"{t / 3600.0:.6g}"})
    return out


def _csv(df: pd.DataFrame, path: str, index=True, units: dict | None = None,
         clock: str | None = None) -> str:
    """Write a table atomically with units in its headers (``name [unit]``:
    :func:`shipthermal.units.with_units`; ``units`` adds or overrides column units, ``clock``
    is the zone of local clock columns)."""
    with atomic_path(path) as tmp:
        with_units(df, units, clock).to_csv(tmp, index=index, float_format="%.6g")
    return path


def _savefig(fig, path: str, figures: FigureOptions | None = None) -> str:
    return os.fspath(save_figure(fig, path, figures or FigureOptions(dpi=100)))


def _hex_rgb(h: str):
    return tuple(int(h[i:i + 2], 16) for i in (1, 3, 5))


def _classification_tables(c, p, out: dict) -> None:
    out["jm_csv"] = _csv(c.jm, p("jm_separability.csv"), units={k: "-" for k in c.jm.columns})
    with atomic_path(p("jm_separability.txt")) as tmp, open(tmp, "w", encoding="utf-8") as fh:
        fh.write("Sample separability (Jeffries-Matusita, eqs. 3-4), all ROI pixels\n" + format_jm_table(c.jm) + "\n")
        spread = c.spread()
        if spread:
            fh.write(f"\nHeld-out accuracy over {spread['n_splits']} ROI splits ({c.split}): mean +- std [min, max]\n")
            for k in ("overall_accuracy", "kappa_quadratic", "kappa_unweighted"):
                v = spread[k]
                fh.write(f"  {k:18s} {v['mean']:.3f} +- {v['std']:.3f}  [{v['min']:.3f}, {v['max']:.3f}]\n")
    out["jm_txt"] = p("jm_separability.txt")
    out["confusion"] = _csv(c.confusion, p("confusion_matrix.csv"),
                            units={k: "pixels" for k in c.confusion.columns})
    spread = c.spread()
    rows = [("overall_accuracy", c.overall_accuracy), ("kappa_quadratic_sklearn", c.kappa_quadratic),
            ("kappa_quadratic_eq5", c.kappa_quadratic_eq5), ("kappa_unweighted", c.kappa_unweighted)]
    std = {"overall_accuracy": "overall_accuracy", "kappa_quadratic_sklearn": "kappa_quadratic",
           "kappa_unweighted": "kappa_unweighted"}
    acc = pd.DataFrame({"metric": [r[0] for r in rows], "value": [r[1] for r in rows],
                        "std_over_splits": [spread[std[r[0]]]["std"] if r[0] in std and spread else np.nan
                                            for r in rows]})
    out["accuracy"] = _csv(acc, p("accuracy.csv"), index=False,
                           units={"value": "-", "std_over_splits": "-"})
    if c.splits is not None:
        out["splits"] = _csv(c.splits, p("accuracy_splits.csv"), index=False,
                             units={k: "-" for k in c.splits.columns
                                    if pd.api.types.is_numeric_dtype(c.splits[k])})
    out["fractions"] = _csv(c.fractions, p("class_fractions.csv"), index=False,
                            units={"fraction": "-"})


def _overpass_rasters(ov, g, p, out: dict) -> None:
    out["qa_mask"] = write_geotiff(p("qa_mask.tif"), ov.mask.astype(np.uint8), g, units="1",
                                   descriptions=["replaced pixels: " + ", ".join(f"{v}={k}" for k, v in MASK_BITS.items())])
    out["water_disagreement"] = write_geotiff(p("water_disagreement.tif"), ov.water_disagreement.astype(np.uint8), g,
                                              units="1",
                                              descriptions=["1 = MNDWI and the water class disagree"])


def write_overpass_outputs(ov, out_dir) -> dict:
    """Write the overpass products (:class:`~.background.OverpassProducts`) into ``out_dir``:
    ``lst_K.tif``, ``class_map.tif``/``.png``, ``qa_mask.tif``, ``water_disagreement.tif``,
    ``lst.png``, the classification tables and ``summary.json``."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out_dir = os.fspath(out_dir)
    os.makedirs(out_dir, exist_ok=True)
    p = lambda name: os.path.join(out_dir, name)  # noqa: E731
    out: dict[str, str] = {}
    g = ov.grid
    nan = np.float32(np.nan)
    out["lst"] = write_geotiff(p("lst_K.tif"), ov.lst.astype(np.float32), g, nodata=nan, units="K",
                               descriptions=[f"surface temperature [K] ({ov.lst_source})"],
                               tags={"time_utc": ov.scene.mtl.acquired_utc.isoformat()})
    out["class_map"] = _class_map_tif(p, ov.class_map, g)
    _overpass_rasters(ov, g, p, out)
    _classification_tables(ov.classification, p, out)
    out["class_map_png"] = _class_png(p, ov.class_map, ov.classification, g)
    b = g.transform
    extent = [b.c / 1000, (b.c + g.shape[1] * b.a) / 1000, (b.f + g.shape[0] * b.e) / 1000, b.f / 1000]
    fig, ax = plt.subplots(figsize=(6.5, 6))
    im = ax.imshow(ov.lst, cmap="inferno", extent=extent)
    fig.colorbar(im, ax=ax, label="LST [K]", shrink=0.8)
    ax.set(title=f"LST ({ov.lst_source}), {ov.scene.mtl.acquired_utc:%Y-%m-%d %H:%M} UTC",
           xlabel="easting [km]", ylabel="northing [km]")
    out["lst_png"] = _savefig(fig, p("lst.png"))
    plt.close(fig)
    summary = {"shape": list(g.shape), "crs": str(g.crs), "overpass_utc": ov.scene.mtl.acquired_utc.isoformat(),
               "lst_K": [float(np.nanmin(ov.lst)), float(np.nanmax(ov.lst))],
               "class_fractions": dict(zip(ov.classification.fractions["class"],
                                           ov.classification.fractions["fraction"].round(4))),
               **ov.summary_extra()}
    with atomic_path(p("summary.json")) as tmp, open(tmp, "w", encoding="utf-8") as fh:
        json.dump(summary, fh, indent=2, default=str)
    out["summary"] = p("summary.json")
    return out


def _class_map_tif(p, class_map, g) -> str:
    cmap_tab = {0: (0, 0, 0, 0), **{c: (*_hex_rgb(CLASS_COLOURS[c]), 255) for c in CLASS_CODES}}
    return write_geotiff(p("class_map.tif"), class_map.astype(np.uint8), g, nodata=0, units="1",
                         tags={"classes": ", ".join(f"{c}={n}" for c, n in CLASS_NAMES.items())},
                         descriptions=["class: " + ", ".join(f"{c}={n}" for c, n in CLASS_NAMES.items())],
                         colormap=cmap_tab)


def _class_png(p, class_map, c, g, figures=None) -> str:
    import matplotlib.pyplot as plt
    from matplotlib.colors import BoundaryNorm, ListedColormap
    from matplotlib.patches import Patch

    b = g.transform
    extent = [b.c / 1000, (b.c + g.shape[1] * b.a) / 1000, (b.f + g.shape[0] * b.e) / 1000, b.f / 1000]
    cmap = ListedColormap(["#000000"] + [CLASS_COLOURS[k] for k in CLASS_CODES])
    norm = BoundaryNorm(np.arange(-0.5, len(CLASS_CODES) + 1.0), cmap.N)
    fig, ax = plt.subplots(figsize=(6.5, 6))
    ax.imshow(class_map, cmap=cmap, norm=norm, extent=extent, interpolation="nearest")
    frac = dict(zip(c.fractions["class"], c.fractions["fraction"]))
    ax.legend(handles=[Patch(color=CLASS_COLOURS[k], label=f"{CLASS_NAMES[k]} ({100 * frac[CLASS_NAMES[k]]:.1f} %)")
                       for k in CLASS_CODES], loc="lower left", fontsize=8)
    sp = c.spread().get("overall_accuracy")
    oa = (f"OA {sp['mean']:.3f} +- {sp['std']:.3f} over {c.spread()['n_splits']} splits" if sp
          else f"OA {c.overall_accuracy:.3f}")
    ax.set(title=f"Land-cover classes ({oa})", xlabel=f"easting [km] ({g.crs})", ylabel="northing [km]")
    add_scale_bar(ax, g.shape[1] * abs(b.a) / 1000.0, colour="black")
    path = _savefig(fig, p("class_map.png"), figures)
    plt.close(fig)
    return path


def write_outputs(bg, out_dir, figures: FigureOptions | None = None) -> dict:
    """Write all products of a :class:`~.background.PortBackground` into ``out_dir``.

    Files: ``lst_K.tif``, ``background_K.tif`` (24 bands, local hours), ``class_map.tif``
    (uint8 with colour table), ``slope_deg.tif``, ``aspect_deg.tif``, ``class_map.png``,
    ``lst.png``, ``background_hours.png``, ``jm_separability.csv``/``.txt``,
    ``confusion_matrix.csv``, ``accuracy.csv``, ``class_fractions.csv``, ``variograms.csv``,
    ``terrain_regression.csv``, ``summary.json``.
    """
    if hasattr(bg, "column_temperature"):
        return write_physical_outputs(bg, out_dir, figures)
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out_dir = os.fspath(out_dir)
    os.makedirs(out_dir, exist_ok=True)
    p = lambda name: os.path.join(out_dir, name)  # noqa: E731
    out: dict[str, str] = {}
    g = bg.grid
    nan = np.float32(np.nan)
    synthetic = bg.synthetic_truth is not None
    out["lst"] = write_geotiff(p("lst_K.tif"), bg.lst.astype(np.float32), g, nodata=nan, units="K",
                               tags={"time_utc": bg.overpass_utc.isoformat()},
                               descriptions=["land surface temperature [K]"
                                             + (" (synthetic scene)" if synthetic else "")])
    origin = _local_midnight(bg.overpass_utc, bg.utc_offset_hours)
    zone = utc_offset_text(bg.utc_offset_hours)
    out["background"] = write_geotiff(
        p("background_K.tif"), bg.temperature.astype(np.float32), g, nodata=nan, units="K",
        descriptions=[f"background temperature [K] at {h:05.2f} h local ({zone})"
                      for h in bg.hours_local],
        band_tags=time_tags(origin, np.asarray(bg.hours_local, float) * 3600.0),
        tags={"local_time_zone": zone})
    out["class_map"] = _class_map_tif(p, bg.class_map, g)
    if bg.overpass is not None:
        _overpass_rasters(bg.overpass, g, p, out)
    out["slope"] = write_geotiff(p("slope_deg.tif"), bg.slope_deg.astype(np.float32), g, nodata=nan,
                                 units="degree", descriptions=["terrain slope [degree]"])
    out["aspect"] = write_geotiff(p("aspect_deg.tif"), bg.aspect_deg.astype(np.float32), g, nodata=nan,
                                  units="degree", descriptions=["terrain aspect [degree] "
                                                                "(clockwise from north)"])

    # --- tables ------------------------------------------------------------------------------
    c = bg.classification
    _classification_tables(c, p, out)
    vrows = [{"hour_local": h, "model": f.model, **f.parameters, "n_points": f.n_points, "Q1": f.q1,
              "Q2": f.q2, "cR": f.cr, "max_lag": f.max_lag, "at_bound": ";".join(f.at_bound)}
             for h, f in zip(bg.hours_local, bg.variograms)]
    out["variograms"] = _csv(pd.DataFrame(vrows), p("variograms.csv"), index=False,
                             units={"hour_local": "h", "psill": "K2", "sill": "K2", "range": "m",
                                    "nugget": "K2", "n_points": "-", "Q1": "-", "Q2": "-",
                                    "cR": "-", "max_lag": "m"})
    t = bg.terrain
    trows = [{"term": "beta1_elevation", "value": t.beta_elevation, "stderr": t.stderr[0], "unit": "K/m"},
             {"term": "beta2_slope", "value": t.beta_slope, "stderr": t.stderr[1], "unit": "K/deg"},
             {"term": "beta3_aspect_southness", "value": t.beta_aspect, "stderr": t.stderr[2], "unit": "K"}]
    trows += [{"term": f"intercept_{k}", "value": v, "stderr": np.nan, "unit": "K"} for k, v in t.intercepts.items()]
    trows += [{"term": "R2", "value": t.r2, "stderr": np.nan, "unit": "-"},
              {"term": "rmse", "value": t.rmse, "stderr": np.nan, "unit": "K"},
              {"term": "n_pixels", "value": t.n_pixels, "stderr": np.nan, "unit": "-"}]
    out["terrain"] = _csv(pd.DataFrame(trows), p("terrain_regression.csv"), index=False,
                          units={"value": "see unit", "stderr": "see unit"})

    # --- pictures ----------------------------------------------------------------------------
    b = g.transform
    extent = [b.c / 1000, (b.c + g.shape[1] * b.a) / 1000, (b.f + g.shape[0] * b.e) / 1000, b.f / 1000]
    out["class_map_png"] = _class_png(p, bg.class_map, c, g, figures)

    fig, ax = plt.subplots(figsize=(6.5, 6))
    im = ax.imshow(bg.lst, cmap="inferno", extent=extent)
    fig.colorbar(im, ax=ax, label="LST [K]", shrink=0.8)
    src = bg.overpass.lst_source if bg.overpass is not None else "single_channel"
    what = "Synthetic port, generated LST (not a real scene)" if synthetic else "Landsat LST"
    ax.set(title=f"{what} ({src}), {bg.overpass_utc:%Y-%m-%d %H:%M} UTC",
           xlabel="easting [km]", ylabel="northing [km]")
    add_scale_bar(ax, g.shape[1] * abs(b.a) / 1000.0)
    out["lst_png"] = _savefig(fig, p("lst.png"), figures)
    plt.close(fig)

    vmin, vmax = np.nanpercentile(bg.temperature, [0.5, 99.5])
    # Every third hour keeps the montage readable and cheap (the GeoTIFF has all 24 layers).
    panels = list(range(0, bg.hours_local.size, 3))
    fig, axes = plt.subplots(2, 4, figsize=(13, 6.8), constrained_layout=True)
    for ax, k in zip(axes.ravel(), panels):
        im = ax.imshow(bg.temperature[k], cmap="inferno", vmin=vmin, vmax=vmax, extent=extent)
        ax.set_title(f"{bg.hours_local[k]:05.2f} h", fontsize=9)
        ax.set_xticks([])
        ax.set_yticks([])
    add_scale_bar(axes.ravel()[0], extent[1] - extent[0])
    fig.colorbar(im, ax=axes, label="background temperature [K]", shrink=0.7)
    label = "synthetic port, " if synthetic else ""
    fig.suptitle(f"Port background every 3 h ({label}paper's chain, {bg.season or 'input'}; "
                 f"local time {utc_offset_text(bg.utc_offset_hours)})")
    out["background_png"] = _savefig(fig, p("background_hours.png"), figures)
    plt.close(fig)

    with atomic_path(p("summary.json")) as tmp, open(tmp, "w", encoding="utf-8") as fh:
        json.dump(bg.summary(), fh, indent=2, default=str)
    out["summary"] = p("summary.json")
    return out


def _local_midnight(overpass_utc, utc_offset_hours: float) -> datetime.datetime:
    """Local midnight (fixed UTC offset [h]) of the local day of an overpass (UTC)."""
    tz = datetime.timezone(datetime.timedelta(hours=float(utc_offset_hours)))
    when = overpass_utc if overpass_utc.tzinfo else overpass_utc.replace(tzinfo=datetime.timezone.utc)
    local = when.astimezone(tz)
    return local.replace(hour=0, minute=0, second=0, microsecond=0)


def write_physical_outputs(bg, out_dir, figures: FigureOptions | None = None) -> dict:
    """Write the products of a :class:`~.physical.PhysicalBackground` into ``out_dir``.

    Files: ``background_K.tif`` (float32 K, 24 bands: the local hours of the first day, each
    band described with its date, time and zone), ``class_map.tif``/``.png``, ``albedo.tif``
    (as used; fitted to the scene when anchored), ``elevation_m.tif``, ``slope_deg.tif``,
    ``aspect_deg.tif``, ``residual_K.tif``, ``surface_resistance_s_m.tif`` (classes fitted
    on their wetness) and ``fit_by_class.csv`` (anchored),
    ``sea.csv`` (hourly: the weather's bulk sea, its skin, the median water pixel),
    ``columns.csv`` (the solved columns), ``background_hours.png``, ``summary.json``.
    Every title and description names what the background is (a synthetic port or the
    scene it is anchored on).
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out_dir = os.fspath(out_dir)
    os.makedirs(out_dir, exist_ok=True)
    p = lambda name: os.path.join(out_dir, name)  # noqa: E731
    out: dict[str, str] = {}
    g = bg.grid
    nan = np.float32(np.nan)
    zone = utc_offset_text(bg.utc_offset_hours)
    day = bg.start
    layers = bg.temperature
    what = bg.label
    out["background"] = write_geotiff(
        p("background_K.tif"), layers.astype(np.float32), g, nodata=nan, units="K",
        descriptions=[f"surface temperature [K], {day:%Y-%m-%d} {int(h):02d}:00 local ({zone}); "
                      f"{what}" for h in bg.hours_local],
        band_tags=time_tags(day, np.asarray(bg.hours_local, float) * 3600.0),
        tags={"local_time_zone": zone, "background": what})
    out["class_map"] = _class_map_tif(p, bg.class_map, g)
    out["albedo"] = write_geotiff(p("albedo.tif"), bg.albedo.astype(np.float32), g, nodata=nan, units="1",
                                  descriptions=["short-wave albedo [-] as used"
                                                + (" (fitted to the scene's LST)"
                                                   if bg.ground.observation is not None else "")])
    gr = bg.ground
    out["elevation"] = write_geotiff(p("elevation_m.tif"), gr.elevation.astype(np.float32), g, nodata=nan,
                                     units="m", descriptions=["elevation [m]"])
    out["slope"] = write_geotiff(p("slope_deg.tif"), gr.slope_deg.astype(np.float32), g, nodata=nan,
                                 units="degree", descriptions=["terrain slope [degree]"])
    out["aspect"] = write_geotiff(p("aspect_deg.tif"), gr.aspect_deg.astype(np.float32), g, nodata=nan,
                                  units="degree", descriptions=["terrain aspect [degree] "
                                                                "(clockwise from north)"])
    if gr.observation is not None:
        res = np.full(bg.class_map.size, np.nan, np.float32)
        res[bg.land] = bg.residual
        out["residual"] = write_geotiff(p("residual_K.tif"), res.reshape(g.shape), g, nodata=nan, units="K",
                                        descriptions=[f"LST minus the fitted model at the overpass "
                                                      f"[K] ({gr.observation.source})"])
        out["fit"] = _csv(pd.DataFrame([f.__dict__ for f in bg.fits]), p("fit_by_class.csv"),
                          index=False, units={k: "see unit" for k in ("median", "p05", "p95")})
        wet = [f.name for f in bg.fits if f.parameter == "surface_resistance"]
        if wet and bg.fitted is not None:
            codes = [c for c, n in CLASS_NAMES.items() if n in wet]
            rs = np.full(bg.class_map.size, np.nan, np.float32)
            sel = np.isin(bg.class_map.ravel()[bg.land], codes)
            rs[bg.land[sel]] = bg.fitted[sel]
            out["surface_resistance"] = write_geotiff(
                p("surface_resistance_s_m.tif"), rs.reshape(g.shape), g, nodata=nan, units="s m-1",
                descriptions=[f"surface resistance r_s [s m-1] fitted to the scene's LST "
                              f"({', '.join(wet)}; inf = dry)"])
    hours = np.arange(0.0, 24.0)
    water = bg.class_map.ravel() == 1
    sea = pd.DataFrame({
        "time_local": [f"{day:%Y-%m-%d} {int(h):02d}:00" for h in hours],
        "sea_bulk_K": np.interp(hours * 3600.0, bg.times_s, bg.sea_bulk),
        "sea_skin_K": [bg.sea_temperature_at(h) for h in hours],
        "water_median_K": [float(np.median(layer.ravel()[water])) if water.any() else np.nan
                           for layer in layers]})
    out["sea"] = _csv(sea, p("sea.csv"), index=False, clock=zone)
    if bg.column_info is not None:
        out["columns"] = _csv(bg.column_info.rename_axis(bg.column_info.index.name or "column"),
                              p("columns.csv"), index=True, units={"column": "-"})

    b = g.transform
    extent = [b.c / 1000, (b.c + g.shape[1] * b.a) / 1000, (b.f + g.shape[0] * b.e) / 1000, b.f / 1000]
    frac = pd.Series(bg.class_map.ravel()).map(CLASS_NAMES).value_counts(normalize=True)

    class _Fractions:        # what _class_png reads of a classification
        fractions = pd.DataFrame({"class": list(CLASS_NAMES.values()),
                                  "fraction": [float(frac.get(n, 0.0)) for n in CLASS_NAMES.values()]})
        overall_accuracy = float("nan")

        @staticmethod
        def spread():
            return {}

    out["class_map_png"] = _class_png(p, bg.class_map, _Fractions, g, figures)
    vmin, vmax = np.nanpercentile(layers, [0.5, 99.5])
    fig, axes = plt.subplots(2, 4, figsize=(13, 6.8), constrained_layout=True)
    for ax, k in zip(axes.ravel(), range(0, 24, 3)):
        im = ax.imshow(layers[k], cmap="inferno", vmin=vmin, vmax=vmax, extent=extent)
        ax.set_title(f"{k:02d}:00", fontsize=9)
        ax.set_xticks([])
        ax.set_yticks([])
    add_scale_bar(axes.ravel()[0], extent[1] - extent[0])
    fig.colorbar(im, ax=axes, label="surface temperature [K]", shrink=0.7)
    fig.suptitle(f"Port background, {day:%Y-%m-%d}, every 3 h (local time {zone})\n{what}; "
                 "surface energy balance driven by the scenario's weather", fontsize=10)
    out["background_png"] = _savefig(fig, p("background_hours.png"), figures)
    plt.close(fig)

    with atomic_path(p("summary.json")) as tmp, open(tmp, "w", encoding="utf-8") as fh:
        json.dump(bg.summary(), fh, indent=2, default=str)
    out["summary"] = p("summary.json")
    return out
