"""The stages of a run, wired from one :class:`~shipthermal.app.scenario.Scenario`.

Used by the command line (:mod:`shipthermal.app.cli`) and the sweeps (:mod:`shipthermal.app.sweep`);
every physical choice lives in the modules called here:

* thermal: :func:`shipthermal.app.thermal.run_scenario_thermal` → ``thermal/<case>/``
  (its products plus ``energy.csv`` and ``history.npz``, the imaging stage's input);
* imaging: :func:`imaging_scenario` turns the same scenario into an
  :class:`imaging.experiment.ImagingScenario` (location, date, time zone, mooring,
  heading, sensor, bands and per-face band emissivities all taken from it; wind, humidity
  and sky from the run's one environment), and :func:`imaging.experiment.run_experiment`
  renders and measures → ``imaging/``.

What each stage receives from a scenario is one function each, so that it can be
inspected without running the stage: :func:`~shipthermal.app.thermal.thermal_inputs`,
:func:`background_inputs`, :func:`imaging_scenario` + :func:`experiment_inputs`,
:func:`output_inputs` (``tests/scenario/test_scenario_reach.py`` checks that every
scenario key reaches the stages that use it).
"""

from __future__ import annotations

import json
import os
import shutil
import time as _time
from pathlib import Path

import numpy as np
import pandas as pd

from imaging.parameters import SENSOR_BANDS
from imaging.thermal_history import ShipThermalHistory

from ..errors import InputError, require
from ..figures import FigureOptions
from ..record_stream import RecordFile
from ..results import EnergyLog, atomic_path, write_vtu_series
from ..units import DAY, HOUR, with_units
from .run_environment import aerosol_conditions, sea_glint_wind_speed, sky_weather
from .scenario import default_scenario
from .thermal import run_scenario_thermal, ship_thermal_history

__all__ = ["QUICK_EDGE_LENGTH", "demo_scenarios", "thermal_case", "store_thermal", "prepare",
           "check_imaging_bands", "output_inputs", "write_thermal", "save_history",
           "load_history", "history_file", "HISTORY_FILES", "background_inputs",
           "build_background", "imaging_scenario", "experiment_inputs", "frame_times",
           "image_cases"]

#: ``demo --quick`` and ``validate --quick`` [m]: the frigate with 1520 triangles. Without
#: ``--quick`` both run the scenario's own mesh: the built-in default
#: (:data:`shipthermal.geometry.DEFAULT_EDGE_LENGTH` per 132 m of length; 59 694 triangles
#: on the frigate).
QUICK_EDGE_LENGTH = 4.0
#: ``demo --quick`` SCR / crossover frame step [s] (the scenario's ``imaging.scr_interval``,
#: default 600 s, is the finest step; coarser frames only for a quick look)
QUICK_SCR_INTERVAL = 1800.0


def demo_scenarios(quick: bool = False, seasons=("summer", "winter")) -> dict:
    """The built-in default scenarios of the demo, one per season.

    They are :func:`~shipthermal.app.scenario.default_scenario` itself; ``quick`` changes
    only the ship's edge length (:data:`QUICK_EDGE_LENGTH`).
    """
    if not quick:
        return {s: default_scenario(s) for s in seasons}
    return {s: default_scenario(s).updated({"ship.edge_length": QUICK_EDGE_LENGTH})
            for s in seasons}


# ---------------------------------------------------------------------------------------
# Thermal stage
# ---------------------------------------------------------------------------------------
def save_history(history, path) -> Path:
    """Write an :class:`imaging.thermal_history.ShipThermalHistory` to ``.npz`` (atomic)."""
    path = Path(path)
    with atomic_path(path) as tmp:
        np.savez_compressed(
            tmp, vertices=history.vertices, faces=history.faces, face_part=history.face_part,
            part_names=np.array(history.part_names, dtype=str), times_s=history.times_s,
            face_temperature=history.face_temperature,
            temp_air=history.temp_air if history.temp_air is not None else np.zeros(0),
            temp_sea=history.temp_sea if history.temp_sea is not None else np.zeros(0),
            label=np.array(history.label),
            period_s=np.array(np.nan if history.period_s is None else history.period_s))
    return path


#: The imaging stage's input in a thermal case folder: one periodic day (``.npz``, in
#: memory) or a weather record's streamed outputs (``.h5``, read lazily by time).
HISTORY_FILES = ("history.npz", "history.h5")


def history_file(case_dir) -> Path:
    """The thermal history in a case folder ``thermal/<case>/`` (:data:`HISTORY_FILES`;
    the ``.npz`` name when neither exists)."""
    d = Path(case_dir)
    for name in HISTORY_FILES:
        if (d / name).is_file():
            return d / name
    return d / HISTORY_FILES[0]


def load_history(path):
    """Read what :func:`save_history` (``.npz``) or the record stream (``.h5``,
    :mod:`shipthermal.record_stream`) wrote; ``path`` may be the case folder."""
    path = Path(path)
    if path.is_dir():
        path = history_file(path)
    if path.suffix == ".h5" and path.is_file():
        return _record_history(path)
    if not path.is_file():
        raise InputError("thermal history", str(path), "must exist (written by the thermal "
                         "stage)", "Run `shipthermal run` first, or resume the run")
    with np.load(path) as d:
        air, sea = d["temp_air"], d["temp_sea"]
        # histories written before the period was stored are one periodic day
        period = float(d["period_s"]) if "period_s" in d.files else DAY
        return ShipThermalHistory(d["vertices"], d["faces"], d["face_part"],
                                  tuple(str(x) for x in d["part_names"]), d["times_s"],
                                  d["face_temperature"], temp_air=air if air.size else None,
                                  temp_sea=sea if sea.size else None, label=str(d["label"]),
                                  period_s=None if np.isnan(period) else period)


def _record_history(path):
    """The history of a weather record's outputs file, face temperatures read lazily."""
    rec = RecordFile(path)
    pm = rec.part_means()
    return ShipThermalHistory(**rec.ship_arrays(), times_s=rec.times,
                              face_temperature=rec.face_temperature,
                              temp_air=pm["temp_air"].to_numpy(),
                              temp_sea=pm["temp_sea_skin"].to_numpy(),
                              label=str(rec.attrs.get("label", "")), period_s=None)


def output_inputs(scenario) -> dict:
    """What the writers receive from a scenario: the run ``directory``, the ``formats``, the
    local hours of the surface maps (``map_hours`` [h]) and the figures' options
    (``figures``: :class:`~shipthermal.figures.FigureOptions`)."""
    return {"directory": scenario.outputs.directory, "formats": tuple(scenario.outputs.formats),
            "map_hours": [s / HOUR for s in scenario.map_seconds()],
            "figures": FigureOptions.from_outputs(scenario.outputs)}


def write_thermal(result, out_dir, scenario, progress: bool = False) -> dict:
    """Write a :class:`~shipthermal.diurnal.DiurnalResult`'s products into ``out_dir``.

    Always: ``part_means.csv``, ``thermal_summary.json``, ``energy.csv`` (per step [J]) and
    the outer-surface temperatures for the imaging stage: ``history.npz`` (a periodic day)
    or ``history.h5`` (a weather record's streamed outputs,
    :mod:`shipthermal.record_stream`). PNG pictures with ``png`` or ``html`` in
    ``outputs.formats``; ``thermal.vtkhdf`` with ``vtkhdf``; a VTU series with ``vtu``
    (a record: its sampled days, :data:`shipthermal.record_stream.SAMPLE_DAYS_MAX`).
    """
    out = Path(out_dir)
    given = output_inputs(scenario)
    fmts = set(given["formats"])
    formats = ["csv", "json"] + (["png"] if fmts & {"png", "html"} else []) \
        + (["vtkhdf"] if "vtkhdf" in fmts else [])
    written = result.write(out, map_hours=given["map_hours"], formats=tuple(formats),
                           progress=progress, figures=given["figures"])
    e = result.energy
    with atomic_path(out / "energy.csv") as tmp:
        with_units(pd.DataFrame({k: getattr(e, k) for k in EnergyLog.FIELDS})).to_csv(
            tmp, index=False, float_format="%.9g")
    written["energy_csv"] = out / "energy.csv"
    if result.record is not None:
        written["history"] = _link_or_copy(result.record.path, out / "history.h5")
    else:
        written["history"] = save_history(ship_thermal_history(result), out / "history.npz")
    if "vtu" in fmts and result.record is not None:
        rec = result.record
        written["vtu"] = write_vtu_series(out / "vtu", result.graph, rec.sample_times,
                                          rec.sample_row)
    elif "vtu" in fmts:
        written["vtu"] = result.results.to_vtu(out / "vtu")
    return written


def _link_or_copy(src, dst) -> Path:
    """``dst`` as a hard link to ``src`` (no copy of a year's outputs), else a copy (another
    file system); atomically either way."""
    dst = Path(dst)
    with atomic_path(dst) as tmp:
        tmp.unlink()
        try:
            os.link(src, tmp)
        except OSError:
            shutil.copyfile(src, tmp)
    return dst


def thermal_case(scenario, run, case: str, *, resume: bool = False, progress: bool = True,
                 log=None, ship=None) -> dict:
    """The thermal stage of one case into ``run`` (a :class:`~shipthermal.app.rundir.RunDir`),
    checkpointed every ``outputs.checkpoint_interval`` of simulated time.

    A finished stage (``thermal/<case>/`` exists) is skipped on ``resume``. Returns the
    run's summary (``thermal_summary.json``).
    """
    stage = f"thermal/{case}"
    if resume and run.has(stage):
        if log:
            log(f"{case}: thermal stage already finished, kept")
        return json.loads((run.path / stage / "thermal_summary.json").read_text())
    ckpt = run.checkpoint(case) if scenario.outputs.checkpoint_interval > 0 else None
    t0 = _time.perf_counter()
    res = run_scenario_thermal(scenario, ship=ship, progress=progress, checkpoint=ckpt,
                               resume=resume, log=log)
    run.record(f"{stage} (solve)", _time.perf_counter() - t0)
    return store_thermal(run, case, res, scenario)


def store_thermal(run, case: str, result, scenario) -> dict:
    """Write a thermal result into ``thermal/<case>/`` of ``run`` (a
    :class:`~shipthermal.app.rundir.RunDir`; :func:`write_thermal`) and record it in the
    manifest. Returns the run's summary (``thermal_summary.json``)."""
    with run.stage(f"thermal/{case}") as tmp:   # the staging folder exists only while writing
        write_thermal(result, tmp, scenario)
    run.manifest["cases"].setdefault(case, {}).update(
        {"days": result.days, "converged": bool(result.converged),
         "surface_faces": int(result.ship.n_faces), "cells": int(result.graph.n_cells),
         "edge_length_m": float(result.ship.edge_length),
         "relative_energy_imbalance": float(result.energy.relative_imbalance)})
    run.save_manifest()
    return result.summary()


# ---------------------------------------------------------------------------------------
# Imaging stage
# ---------------------------------------------------------------------------------------
def background_inputs(scenario) -> tuple[str, dict]:
    """What the background stage receives from a scenario.

    ``("physical", {...})``: the surface energy balance of every pixel
    (:func:`imaging.background.physical.build_physical_background`) under the run's one
    environment (``environment``, the thermal stage's own object), its ground the synthetic
    port around ``[location]`` (``ground``:
    ``{"kind": "synthetic", ...}``) or a Landsat scene with ROIs and an optional DEM
    (``{"kind": "files", ...}``); ``("builtin", ...)`` / ``("files", ...)``: the paper's chain
    (keyword arguments of :func:`imaging.background.build_port_background` /
    :func:`imaging.background.build_background_from_files`).
    """
    bgs = scenario.background
    if bgs.model == "physical":
        if bgs.source == "builtin":
            ground = dict(kind="synthetic", latitude=scenario.location.latitude,
                          longitude=scenario.location.longitude, size_px=bgs.size_px,
                          seed=bgs.seed)
        else:
            ground = dict(kind="files", mtl=bgs.mtl, roi=bgs.roi, dem=bgs.dem,
                          band_files=bgs.band_files, use_qa=bgs.qa_mask, seed=bgs.seed,
                          n_splits=bgs.roi_splits, dem_nodata=bgs.dem_nodata)
        return "physical", dict(ground=ground, residual=bgs.residual, classes=_plain(bgs.classes),
                                end_s=record_span_s(scenario),
                                environment=scenario.environment())
    if bgs.source == "builtin":
        return "builtin", dict(season=scenario.time.season, seed=bgs.seed, size_px=bgs.size_px,
                               lat=scenario.location.latitude,
                               lon=scenario.location.longitude,
                               krige_coarsen=bgs.krige_coarsen,
                               variogram_model=bgs.variogram_model, n_splits=bgs.roi_splits,
                               krige_statistics=bgs.krige_statistics)
    for key in ("dem", "met"):
        if getattr(bgs, key) is None:
            raise InputError(f"background.{key}", None, "is required with model = 'paper' and "
                             "source = 'files' for the hourly background of the imaging stage",
                             "Add it to [background], or use model = 'physical' (no met grid "
                             "needed; `shipthermal background` writes the overpass products)")
    offset = scenario.start.utcoffset().total_seconds() / HOUR
    return "files", dict(mtl_path=bgs.mtl, dem_path=bgs.dem, met_path=bgs.met, roi_path=bgs.roi,
                         season=scenario.time.season, utc_offset_hours=offset,
                         variogram_model=bgs.variogram_model, krige_coarsen=bgs.krige_coarsen,
                         seed=bgs.seed, band_files=bgs.band_files, use_qa=bgs.qa_mask,
                         n_splits=bgs.roi_splits, met_variable=bgs.met_variable,
                         met_units=bgs.met_units, met_margin_cells=bgs.met_margin_cells,
                         krige_statistics=bgs.krige_statistics, dem_nodata=bgs.dem_nodata)


def _plain(mapping) -> dict:
    """A scenario's read-only table as plain nested dicts and lists."""
    if hasattr(mapping, "items"):
        return {k: _plain(v) for k, v in mapping.items()}
    if isinstance(mapping, tuple):
        return [_plain(v) for v in mapping]
    return mapping


def record_span_s(scenario) -> float | None:
    """Length of a weather record's run [s] (``weather.day = 'record'``); None for a
    periodic day."""
    if scenario.weather.day != "record" or scenario.weather.source == "builtin":
        return None
    env = scenario.environment()
    return float((env.weather.time[-1] - env.start).total_seconds())


def _ground(spec: dict, progress: bool = False):
    """The :class:`imaging.background.physical.GroundCover` of ``background_inputs``."""
    # deferred: imaging.background loads scikit-learn, pykrige and scipy.stats (0.8 s of every
    # command's start-up, measured)
    from imaging.background.physical import ground_from_overpass, ground_from_synthetic

    spec = dict(spec)
    kind = spec.pop("kind")
    if kind == "synthetic":
        return ground_from_synthetic(**spec)
    # deferred as above (and looked up here: tests replace the overpass and scene readers)
    from imaging.background.background import build_overpass
    from imaging.background.landsat import read_landsat_scene
    from imaging.background.terrain import load_dem

    scene = read_landsat_scene(spec["mtl"], None, band_files=spec["band_files"],
                               use_qa=spec["use_qa"])
    ov = build_overpass(scene, spec["roi"], seed=spec["seed"], n_splits=spec["n_splits"])
    elevation, note = None, ""
    if spec["dem"] is not None:
        dem = load_dem(spec["dem"], ov.grid, fill_voids=spec["dem_nodata"] == "fill")
        elevation = dem.elevation
        note = "; ".join(dem.notes)
        if spec["dem_nodata"] == "error" and not np.isfinite(elevation).all():
            raise InputError("background.dem", spec["dem"], f"{int((~np.isfinite(elevation)).sum())} "
                             "scene pixels have no elevation (voids or outside the DEM)",
                             "Set background.dem_nodata = 'fill' or 'mask' (masked: level there)")
    return ground_from_overpass(ov, elevation, dem_note=note)


def build_background(scenario, progress: bool = False):
    """The port background of ``[background]``: by default the physical model over the
    synthetic port (around ``[location]``) or a real scene, driven by the scenario's one
    environment; with ``model = 'paper'`` the paper's chain."""
    kind, kwargs = background_inputs(scenario)
    if kind == "physical":
        # deferred: imaging.background loads scikit-learn, pykrige and scipy.stats (0.8 s
        # of every command's start-up, measured)
        from imaging.background.physical import build_physical_background
        from imaging.background.surface_classes import apply_overrides

        return _reading_rasters(scenario, lambda: build_physical_background(
            _ground(kwargs["ground"], progress), kwargs["environment"],
            end_s=kwargs["end_s"], residual=kwargs["residual"],
            classes=apply_overrides(kwargs["classes"]), progress=progress))
    if kind == "builtin":
        # deferred: imaging.background loads scikit-learn, pykrige and scipy.stats (0.8 s
        # of every command's start-up, measured)
        from imaging.background import build_port_background

        return build_port_background(**kwargs)
    # deferred: imaging.background (0.8 s of every command's start-up, measured)
    from imaging.background import build_background_from_files

    return _reading_rasters(scenario, lambda: build_background_from_files(
        **kwargs, progress=progress))


def _reading_rasters(scenario, build):
    """``build()``, with GDAL's failures to open a raster the scenario names reported as a
    user error on its key rather than as a crash."""
    # lazy: rasterio takes half a second to import (measured)
    from rasterio.errors import RasterioIOError

    bgs = scenario.background
    try:
        return build()
    except RasterioIOError as exc:
        text = str(exc)
        key = next((k for k in ("dem", "roi", "mtl", "met") if getattr(bgs, k) and
                    Path(getattr(bgs, k)).name in text), "files")
        raise InputError(f"background.{key}", getattr(bgs, key, None) or text,
                         f"must be a readable raster (GDAL: {text})",
                         "Give a GeoTIFF (DEM, ROI labels) or the Landsat bands named in the "
                         "MTL") from None


def imaging_scenario(scenario, background, ship):
    """The :class:`imaging.experiment.ImagingScenario` of a scenario for ``ship`` (the
    thermal history's or the scenario's ship: ``vertices``, ``faces``, ``face_part``,
    ``part_names``).

    Everything comes from the one scenario: location, date and time zone (sun), the
    mooring position (``[east, north]`` of the scene centre) and heading, the view
    direction, samples per pixel, ray tracer, atmosphere backend and model, detector
    effects, the camera, and each face's band emissivity (sub-parts with their own values,
    :meth:`Scenario.face_property <shipthermal.app.scenario.Scenario.face_property>`). The
    weather comes from the run's one environment (:meth:`Scenario.environment
    <shipthermal.app.scenario.Scenario.environment>`, :mod:`.run_environment`): the day's
    mean wind (sea glint), wind and humidity (aerosol) and near-surface weather (the
    image's thermal sky follows the thermal stage's).
    """
    # deferred: the renderer and the atmosphere add 70 ms to every command's start-up
    # (measured)
    from imaging.experiment import ImagingScenario
    from imaging.render import SensorOptions
    from imaging.scene import ShipPlacement, as_scene_background

    sc = scenario
    img = sc.imaging
    grid = as_scene_background(background)
    ny, nx = grid.shape
    res = grid.resolution_m
    mx, my = sc.ship.mooring_position
    placement = ShipPlacement(0.5 * nx * res + mx, 0.5 * ny * res + my, sc.ship.heading)
    sens = img.sensor
    if sens.quantisation_bits:
        raise InputError("imaging.sensor.quantisation_bits", sens.quantisation_bits,
                         "is not supported by the command line yet (quantisation needs a "
                         "radiance range per band)", "Set it to 0")
    options = None
    if sens.own_netd:
        inst = sc.instrument()
        options = {b.key: SensorOptions(psf=sens.psf, netd_k=b.netd_K, seed=sc.solver.seed)
                   for b in inst.bands}
    elif sens.psf or (sens.netd_k or 0.0) > 0:
        options = SensorOptions(psf=sens.psf, netd_k=sens.netd_k or None, seed=sc.solver.seed)
    emissivity = {band: sc.face_property(ship, "emissivity", band) for band in sc.bands}
    users = (tuple(b.response for b in sc.instrument().bands) if sens.preset == "user"
             else ())
    env = sc.environment()
    return ImagingScenario(
        season=sc.atmosphere_season, atmosphere_model=sc.atmosphere_model,
        atmosphere_by_day=sc.atmosphere_by_day,
        cloud_type=img.atmosphere.cloud_type, background=background, date=str(sc.time.date),
        latitude=sc.location.latitude, longitude=sc.location.longitude,
        tz=sc.location.time_zone, wind_speed=sea_glint_wind_speed(env), placement=placement,
        view_zenith_deg=sens.view_zenith_deg, view_azimuth_deg=sens.view_azimuth_deg,
        samples_per_pixel=img.samples_per_pixel_side, backend=sc.solver.backend,
        atmosphere_backend=img.atmosphere.backend, sensor_options=options,
        renderer_options={"ship_emissivity": emissivity, "sensor": sc.sensor()},
        sky_weather=sky_weather(env), aerosol=aerosol_conditions(env), user_bands=users)


def experiment_inputs(scenario, step_s: float | None = None) -> dict:
    """What the imaging run receives from a scenario besides its
    :func:`imaging_scenario`: ``bands``, frame ``times`` [s] (:func:`frame_times`),
    ``typical_hours`` of the image panels [h] and ``shared_panel_scale``."""
    return {"bands": scenario.bands, "times": frame_times(scenario, step_s),
            "typical_hours": tuple(s / HOUR for s in scenario.image_seconds()),
            "shared_panel_scale": scenario.imaging.panel_colour_scale == "shared"}


def frame_times(scenario, step_s: float | None = None) -> np.ndarray:
    """SCR / crossover frame times [s after local midnight of ``time.date``]: every
    ``imaging.scr_interval`` (or ``step_s``, a quick look) over the day, or over the whole
    span of a weather record."""
    step = float(step_s or scenario.imaging.scr_interval)
    if not (60.0 <= step <= 3 * HOUR):
        raise InputError("step", step, "must lie in [60, 10800] s (1 min to 3 h)")
    end = record_span_s(scenario)
    return np.arange(0.0, (DAY if end is None else end) + 1.0, step)


IMAGING_BANDS = SENSOR_BANDS
"""The bands the renderer draws: the paper's two and the real sensors' named bands (the
atmosphere tables hold each, :data:`imaging.parameters.SENSOR_BANDS`), and a user sensor's
band ``"user"`` (its response integrated from the tables' spectra)."""


def check_imaging_bands(scenario) -> None:
    """The imaging stage renders the named bands and a user sensor's; the scenario also
    accepts custom 'lo-hi' bands (thermal emissivities), which imaging cannot take: say so
    up front. A weather record is imaged over its whole span only with the physical
    background (the paper's chain is one day of a met grid)."""
    if (scenario.weather.day == "record" and scenario.weather.source != "builtin"
            and scenario.background.model == "paper"):
        raise InputError("background.model", "paper", "images one periodic day (a same-day "
                         "met grid); a weather record is imaged with the physical background",
                         "Set background.model = 'physical', or image one day with "
                         "weather.day = 'periodic'")
    user = ("user",) if scenario.imaging.sensor.preset == "user" else ()
    other = [b for b in scenario.bands if b not in IMAGING_BANDS + user]
    if other:
        raise InputError("imaging.bands", list(scenario.bands), "the imaging stage takes the "
                         "named bands of the atmosphere tables ('3-5', '8-14' and the "
                         "sensor presets' bands) and a user sensor's band; "
                         f"{other[0]!r} is not one (a custom rectangle is available through "
                         "imaging.atmosphere, not in the imaging run)",
                         'Use "3-5" / "8-14" or a sensor preset, give the band as a user '
                         'sensor ([imaging.sensor] preset = "user", response_file), or run '
                         'the thermal stage only')


def prepare(scenario, imaging: bool = False, progress: bool = False, log=None):
    """Read every input file of a scenario before anything is written: build the ship
    (mesh files), the weather record (weather file) and, with ``imaging``, the port
    background (rasters). A bad file raises :class:`InputError` here, so a failed run
    leaves no folder behind.

    Returns ``(ship, background or None)``; ``log`` receives one line per mesh repair.
    """
    if imaging:
        check_imaging_bands(scenario)
    ship, ship_report = scenario.ship(return_report=True)
    for line in ship_report.get("repairs", []) if log else ():
        log(f"ship: {line}")
    scenario.environment()
    if imaging:
        scenario.atmosphere_model      # the site rule must place the day before any run
    background = build_background(scenario, progress=progress) if imaging else None
    return ship, background


def image_cases(cases: dict, out_dir, progress: bool = True, log=None,
                step_s: float | None = None, backgrounds: dict | None = None) -> dict:
    """Image thermal histories: ``cases = {case: (scenario, history)}``.

    Cases of distinct atmosphere seasons and equal bands and frame times go into one
    :func:`imaging.experiment.run_experiment` (so the panels and SCR plots put summer and
    winter side by side, like the paper); otherwise each case gets ``out_dir/<case>/``.

    ``step_s`` replaces ``imaging.scr_interval`` as the frame step [s] (quick looks);
    ``backgrounds = {case: background}`` reuses backgrounds built before. Each case's port
    background goes to ``<group>/background/<case>/`` (GeoTIFFs in K, class map, tables).
    Returns ``{group folder: ExperimentResult}`` and writes the products.
    """
    # deferred: the background's writers (scikit-learn, pykrige) and the renderer, 0.9 s of
    # every command's start-up (measured)
    from imaging.background.outputs import write_outputs
    from imaging.experiment import run_experiment

    for sc, _ in cases.values():
        check_imaging_bands(sc)
    say = log or (lambda m: None)
    out = Path(out_dir)
    seasons = [sc.atmosphere_season for sc, _ in cases.values()]
    first = next(iter(cases.values()))[0]
    together = (len(set(seasons)) == len(seasons)
                and all(sc.bands == first.bands and sc.imaging.scr_interval
                        == first.imaging.scr_interval for sc, _ in cases.values()))
    groups = {"": dict(cases)} if together else {c: {c: v} for c, v in cases.items()}
    results = {}
    for folder, group in groups.items():
        hist, scen, typical = {}, {}, {}
        for case, (sc, h) in group.items():
            season = sc.atmosphere_season
            t0 = _time.perf_counter()
            bg = (backgrounds or {}).get(case)
            if bg is None:
                say(f"{case}: building the port background")
                bg = build_background(sc, progress=progress)
            say(f"{case}: writing the port background (GeoTIFFs, class map, tables)")
            write_outputs(bg, (out / folder if folder else out) / "background" / case,
                          figures=FigureOptions.from_outputs(sc.outputs))
            say(f"{case}: port background, written ({_time.perf_counter() - t0:.1f} s)")
            scen[season] = imaging_scenario(sc, bg, h)
            hist[season] = h
            typical[season] = experiment_inputs(sc, step_s)["typical_hours"]
        given = experiment_inputs(next(iter(group.values()))[0], step_s)
        target = out / folder if folder else out
        t0 = _time.perf_counter()
        record = any(record_span_s(sc) is not None for sc, _ in group.values())
        say(f"imaging {'+'.join(hist)}: {len(given['times'])} frames per band and season, "
            "then the products (NetCDF, GeoTIFF, panels, SCR curves)")
        results[folder] = run_experiment(hist, target, bands=given["bands"],
                                         times=given["times"], progress=progress,
                                         scenarios=scen, typical_hours=typical,
                                         shared_panel_scale=given["shared_panel_scale"],
                                         stack_step_s=HOUR if record else None,
                                         figures=FigureOptions.from_outputs(first.outputs))
        say(f"imaging {'+'.join(hist)} x {', '.join(given['bands'])} µm "
            f"({_time.perf_counter() - t0:.1f} s)")
    require(bool(results), "cases", cases, "must hold at least one case")
    return results
