"""Every scenario key reaches every stage that uses it (sub-parts included).

For each key of the schema (:func:`schema_keys`, so a new key must be listed here) one
scenario is loaded with that key changed, and what the wiring hands to each stage is
compared with the unchanged scenario's — without running any stage:

* ``thermal``    — :func:`shipthermal.app.thermal.thermal_inputs` (ship geometry and
  layups, the environment evaluated every 30 min, settings, per-part optics, checkpoints);
* ``background`` — :func:`shipthermal.app.pipeline.background_inputs` (the physical
  model's environment evaluated every 30 min in the fields it uses: the same weather,
  sun and sea as the ship's, so every weather key must reach it);
* ``imaging``    — :func:`shipthermal.app.pipeline.imaging_scenario` (sun, placement,
  view, per-face band emissivities, sensor, sea-glint wind, aerosol, sky weather) and
  :func:`~shipthermal.app.pipeline.experiment_inputs`, for one fixed ship: the imaging
  renders the thermal stage's ship (its history), so the ship's geometry reaches it
  through the thermal stage;
* ``outputs``    — :func:`shipthermal.app.pipeline.output_inputs`.

A stage whose inputs cannot be built with the changed key (a refusal, e.g. a weather
record for the imaging stage) counts as reached: the key got there. Keys that reach no
stage are listed in :data:`REACHES_NO_STAGE` with the reason.
"""

from __future__ import annotations

import dataclasses
import shutil
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from shipthermal.app.calendar import calendar_inputs
from shipthermal.app.pipeline import (background_inputs, check_imaging_bands, experiment_inputs,
                                      imaging_scenario, output_inputs)
from shipthermal.app.scenario import load_scenario, schema_keys
from shipthermal.app.thermal import thermal_inputs
from shipthermal.errors import InputError

ROOT = Path(__file__).resolve().parents[2]
NDBC = ROOT / "tests" / "data" / "weather" / "44009h2013_mar03-09.txt"
PORT = ROOT / "examples" / "real_port" / "data"
DEM = ROOT / "tests" / "data" / "dem" / "srtm_N49W124_crop.tif"
MET = ROOT / "tests" / "data" / "met" / "era5_t2m_2019-03-01_02_uk.grib"

T, B, I, O, C = "thermal", "background", "imaging", "outputs", "calendar"

# ---------------------------------------------------------------------------------------
# base scenarios (small: a coarse patrol boat, a 100-pixel port)
# ---------------------------------------------------------------------------------------
TINY = {"time": {"season": "summer", "output_interval": 3600.0},
        "ship": {"builtin": "patrol_boat", "edge_length": 5.6, "mooring_position": [90.0, 30.0]},
        "solver": {"time_step": 1800.0},
        "background": {"size_px": 100},
        "outputs": {"checkpoint_interval": 3600.0}}

BUOY = {"location": {"latitude": 38.46, "longitude": -74.70, "time_zone": "Etc/GMT+5"},
        "time": {"date": "2013-03-04", "season": "winter"},
        "weather": {"source": "buoy.txt", "wind_height": 5.0, "cloud_cover": 0.5}}

CSV = {"location": {"latitude": 38.46, "longitude": -74.70, "time_zone": "Etc/GMT+5"},
       "time": {"date": "2023-07-15"},
       "weather": {"source": "w.csv", "temp_sea": 296.0, "cloud_cover": 0.4,
                   "wind_direction": 180.0}}


def _merge(*parts) -> dict:
    """Deep merge of nested dicts; a value None removes the key."""
    out: dict = {}
    for p in parts:
        for k, v in p.items():
            if v is None:
                out.pop(k, None)
            else:
                out[k] = _merge(out.get(k, {}), v) if isinstance(v, dict) else v
    return out


EPW_HEADER = [
    "LOCATION,Dalian,LN,CHN,SYNTHETIC,546620,38.91,121.63,8.0,92.0", "DESIGN CONDITIONS,0",
    "TYPICAL/EXTREME PERIODS,0", "GROUND TEMPERATURES,0", "HOLIDAYS/DAYLIGHT SAVINGS,No,0,0,0",
    "COMMENTS 1,written by the shipthermal test suite", "COMMENTS 2,",
    "DATA PERIODS,1,1,Data,Sunday, 7/15, 7/16"]


def _write_epw(path):
    rows = []
    for i in range(48):
        day, hour = 15 + i // 24, i % 24 + 1
        ghi = max(0.0, 800.0 * np.sin(2 * np.pi * (hour - 6) / 24))
        # the 35 EnergyPlus weather-file fields, in order
        f = [2023, 7, day, hour, 0, "?9?9?9?9E0?9?9?9?9?9?9?9?9?9?9?9?9?9?9?9*9*9?9?9?9",
             20 + (i % 24) / 4, 18.0, 80, 101000, 9999, 9999, 390 + i, round(ghi, 1), 0, 0,
             999999, 999999, 999999, 9999, (170 + i) % 360, 3.5, 5, 5, 9999, 99999, 9,
             999999999, 999, 0.999, 999, 99, 999, 0, 0]
        rows.append(",".join(str(x) for x in f))
    path.write_text("\n".join(EPW_HEADER + rows) + "\n")


def _write_csv(path, extra=()):
    t = pd.date_range("2023-07-14 00:00", periods=72, freq="h")
    h = np.arange(len(t))
    cols = {"time": t.strftime("%Y-%m-%dT%H:%M:%S"),
            "temp_air": 24.0 + 4.0 * np.sin(2 * np.pi * (h - 9) / 24),
            "relative_humidity": 75.0 + 5.0 * np.cos(2 * np.pi * h / 24),
            "wind_speed": 3.0 + 0.05 * h}
    if "cloud_cover" in extra:
        cols["cloud_cover"] = 0.3 + 0.2 * np.sin(2 * np.pi * h / 24) ** 2
    if "ghi" in extra:
        cols["ghi"] = np.clip(800.0 * np.sin(2 * np.pi * (h - 6) / 24), 0.0, None)
    if "longwave_down" in extra:
        cols["longwave_down"] = 380.0 + 10.0 * np.sin(2 * np.pi * h / 24)
    pd.DataFrame(cols).to_csv(path, index=False)


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    d = tmp_path_factory.mktemp("reach")
    shutil.copy(NDBC, d / "buoy.txt")
    from imaging.overpass import SATELLITES

    (d / "sat.tle").write_text("LANDSAT 8\n" + "\n".join(SATELLITES["landsat8"].tle) + "\n")
    text = NDBC.read_text().splitlines()
    row = text[30].split()
    row[13] = f"{float(row[13]) + 2.0:.1f}"            # ATMP of one hour 2 K warmer
    (d / "buoy2.txt").write_text("\n".join(text[:30] + [" ".join(row)] + text[31:]) + "\n")
    _write_csv(d / "w.csv")
    _write_csv(d / "w_cloud.csv", ("cloud_cover",))
    _write_epw(d / "a.epw")
    from shipthermal.geometry import patrol_boat, write_ship

    import trimesh

    write_ship(patrol_boat(edge_length=5.6), d, stem="boat")
    hull = trimesh.util.concatenate([trimesh.load(d / "boat_parts" / f"hull_{w}.stl")
                                     for w in ("wetted", "dry")])
    hull.export(d / "boat_parts" / "hull.stl")
    deck = trimesh.load(d / "boat_parts" / "deck.stl")
    deck.apply_translation([0.0, 0.0, 0.05])
    deck.export(d / "boat_parts" / "deck_moved.stl")
    return d


def bases(d: Path) -> dict:
    ship_files = {"ship": {"builtin": None, "files": {"mesh": "boat.ply",
                                                      "part_map": "boat_parts.json",
                                                      "units": "m"}}}
    parts = {"ship": {"builtin": None, "files": {
        "parts": {p: f"boat_parts/{p}.stl" for p in (
            "hull", "deck", "superstructure", "superstructure_funnel", "superstructure_gun",
            "superstructure_mast")}, "units": "m", "draught": 2.7}}}
    return {
        "builtin": TINY,
        "parametric": _merge(TINY, {"ship": {"parameters": {"length": 60.0}}}),
        "buoy": _merge(TINY, BUOY),
        "record": _merge(TINY, BUOY, {"weather": {"day": "record", "days": 2}}),
        "csv": _merge(TINY, CSV),
        "csv_cloud": _merge(TINY, CSV, {"weather": {"source": "w_cloud.csv"}}),
        "epw": _merge(TINY, {"time": {"date": "2023-07-15"},
                             "weather": {"source": "a.epw", "temp_sea": 295.0,
                                         "use_measured_irradiance": True,
                                         "use_measured_longwave": True}}),
        "ship_files": _merge(TINY, ship_files),
        "ship_parts": _merge(TINY, parts),
        "paper": _merge(TINY, {"background": {"model": "paper"}}),
        "cal_swath": _merge(TINY, {"calendar": {"swath": 185000.0}}),
        "cal_years": _merge(TINY, {"calendar": {"years": [2023]}}),
        # a user's material in the funnel's layup
        "own_material": _merge(TINY, {"materials": {"own": dict(OWN_MATERIAL)},
                                      "ship": {"layups": {FUNNEL: [
                                          {"material": "own", "thickness": 0.008}]}}}),
        "bg_physical": _merge(TINY, {"background": {
            "source": "files", "mtl": str(PORT / "LC08_L2SP_204023_20200927_20201006_02_T1_MTL.txt"),
            "roi": str(PORT / "mersey_rois.geojson"), "size_px": None}}),
        "bg_files": _merge(TINY, {"background": {
            "source": "files", "mtl": str(PORT / "LC08_L2SP_204023_20200927_20201006_02_T1_MTL.txt"),
            "roi": str(PORT / "mersey_rois.geojson"), "dem": str(DEM), "met": str(MET),
            "size_px": None}}),
    }


# ---------------------------------------------------------------------------------------
# key → (base, changed value, stages it must reach)
# ---------------------------------------------------------------------------------------
FUNNEL = "superstructure_funnel"          # a sub-part: takes its main part's value otherwise
OWN_MATERIAL = {"conductivity": 50.0, "density": 7850.0, "specific_heat": 470.0,
                "source": "test plate"}

CASES = {
    "name": ("builtin", "other", {O}),
    "description": ("builtin", "changed text", set()),
    "location.latitude": ("builtin", 39.5, {T, B, I}),
    "location.longitude": ("builtin", 122.0, {T, B, I}),
    "location.time_zone": ("builtin", "Etc/GMT-9", {T, B, I}),
    "location.altitude": ("builtin", 200.0, {T, B}),
    "time.season": ("builtin", "winter", {T, B, I, O}),
    "time.date": ("builtin", "2023-07-25", {T, B, I}),
    "time.output_interval": ("builtin", 7200.0, {T}),
    "time.map_times": ("builtin", ["09:30"], {O}),
    "weather.source": ("buoy", "buoy2.txt", {T, B, I}),
    "weather.format": ("csv", "tmy3", {T, B, I}),             # the wrong reader: refused
    "weather.day": ("buoy", "record", {T, B, I}),          # the record's span everywhere
    "weather.days": ("record", 1, {T, B, I}),
    "weather.wind_height": ("buoy", 10.0, {T, B, I}),
    "weather.max_gap_hours": ("buoy", 0.5, {T, B, I}),        # the buoy's gaps: refused
    "weather.temp_sea": ("csv", 290.0, {T, B}),
    "weather.cloud_cover": ("csv", 0.8, {T, B, I}),
    "weather.wind_direction": ("csv", 90.0, {T}),
    "weather.temp_unit": ("csv", "K", {T, B, I}),             # 24 K air: refused
    "weather.cloud_unit": ("csv_cloud", "percent", {T, B, I}),
    "weather.year": ("builtin", None, set()),
    "weather.max_site_distance": ("epw", 500.0, set()),
    "weather.use_measured_irradiance": ("epw", False, {T, B}),
    "weather.use_measured_longwave": ("epw", False, {T, B, I}),
    "weather.clear_sky_model": ("builtin", "prata", {T, B, I}),
    "weather.cloud_model": ("builtin", "crawford_duchon", {T, B, I}),
    "weather.decomposition": ("epw", "dirint", {T, B}),
    "weather.linke_turbidity": ("builtin", 5.0, {T, B}),
    "weather.sea_emissivity": ("builtin", 0.95, {T}),
    "weather.sea_skin": ("builtin", "none", {T, B}),       # the imaging: via the history
    "weather.wind_speed_offset": ("builtin", 2.0, {T, B, I}),
    "weather.temp_air_offset": ("builtin", 1.0, {T, B, I}),
    "weather.cloud_cover_offset": ("builtin", 0.2, {T, B, I}),
    "ship.builtin": ("builtin", "frigate", {T}),
    "ship.parameters.length": ("parametric", 70.0, {T}),
    "ship.parameters.beam": ("parametric", 9.0, {T}),
    "ship.parameters.draught": ("parametric", 2.5, {T}),
    "ship.parameters.freeboard": ("parametric", 4.0, {T}),
    "ship.superstructure_material": ("builtin", "aluminium_5083", {T}),
    "ship.files.units": ("ship_files", "mm", {T}),      # a 56 mm boat: refused
    "ship.files.mesh": ("ship_parts", None, {T}),       # see _change: parts → one mesh
    "ship.files.part_map": ("ship_files", "auto", {T}),
    "ship.files.parts.<part>": ("ship_parts", None, {T}),
    "ship.files.draught": ("ship_parts", 2.5, {T}),
    "ship.files.waterline_z": ("ship_files", 0.5, {T}),
    "ship.files.clean": ("ship_files", True, set()),
    "ship.files.fix_normals": ("ship_files", True, set()),
    "ship.files.repair": ("ship_files", "union", set()),
    "ship.files.repair_edge_length": ("ship_files", 3.0, set()),
    "ship.files.max_repair_change": ("ship_files", 0.05, set()),
    "ship.files.check_scale": ("ship_files", False, set()),
    "ship.edge_length": ("builtin", 4.0, {T}),
    "ship.heading": ("builtin", 30.0, {T, I}),
    "ship.speed": ("builtin", 2.0, {T}),
    "ship.mooring_position": ("builtin", [60.0, 30.0], {I}),
    "ship.layups.<part>": ("builtin", None, {T}),
    "ship.layups.<part>[i].material": ("builtin", None, {T}),
    "ship.layups.<part>[i].thickness": ("builtin", None, {T}),
    "ship.layups.<part>[i].cells": ("builtin", None, {T}),
    "ship.layups.<part>[i].solar_absorptivity": ("builtin", None, {T}),
    "ship.layups.<part>[i].longwave_emissivity": ("builtin", None, {T}),
    "materials.<name>.conductivity": ("own_material", 45.0, {T}),
    "materials.<name>.density": ("own_material", 7800.0, {T}),
    "materials.<name>.specific_heat": ("own_material", 480.0, {T}),
    "materials.<name>.source": ("own_material", "another data sheet", {T}),
    "ship.compartment_temperature.<part>": ("builtin", {FUNNEL: 320.0}, {T}),
    "ship.solar_absorptivity.<part>": ("builtin", {FUNNEL: 0.9}, {T}),
    "ship.longwave_emissivity.<part>": ("builtin", {FUNNEL: 0.6}, {T}),
    "ship.band_emissivity.<part>.<band>": ("builtin", {FUNNEL: {"3-5": 0.6}}, {I}),
    "solver.time_step": ("builtin", 900.0, {T}),
    "solver.night_step": ("builtin", 600.0, {T}),
    "solver.scheme": ("builtin", "crank_nicolson", {T}),
    "solver.spinup_tolerance": ("builtin", 0.05, {T}),
    "solver.spinup_max_days": ("builtin", 3, {T}),
    "solver.rays_per_face": ("builtin", 32, {T}),
    "solver.samples_per_face": ("builtin", 8, {T}),
    "solver.seed": ("builtin", 7, {T}),
    "solver.backend": ("builtin", "numba", {T, I}),
    "solver.jobs": ("builtin", 2, {T}),
    "convection.model": ("builtin", "iso6946", {T}),
    "convection.parts.<part>": ("builtin", {FUNNEL: "doe2"}, {T}),
    "convection.roughness.<part>": ("builtin", {FUNNEL: "rough"}, {T}),
    "background.source": ("builtin", "files", {B}),
    "background.model": ("builtin", "paper", {B}),
    "background.residual": ("bg_physical", "constant", {B}),
    "background.classes.<class>.<property>": ("builtin", {"land": {"albedo": 0.15}}, {B}),
    "background.seed": ("builtin", 5, {B}),
    "background.size_px": ("builtin", 120, {B}),
    "background.mtl": ("bg_files", None, {B}),
    "background.dem": ("bg_files", None, {B}),
    "background.met": ("bg_files", None, {B}),
    "background.roi": ("bg_files", None, {B}),
    "background.krige_coarsen": ("paper", 3, {B}),
    "background.variogram_model": ("paper", "exponential", {B}),
    "background.band_files": ("bg_files", "l8_{band}.tif", {B}),
    "background.qa_mask": ("bg_files", False, {B}),
    "background.roi_splits": ("paper", 4, {B}),
    "background.met_variable": ("bg_files", "t2m", {B}),
    "background.met_units": ("bg_files", "K", {B}),
    "background.met_margin_cells": ("bg_files", 3, {B}),
    "background.krige_statistics": ("paper", True, {B}),
    "background.dem_nodata": ("bg_files", "fill", {B}),
    "background.water_vapour": ("bg_files", 2.0, set()),
    "imaging.bands": ("builtin", ["8-14"], {I}),
    "imaging.times": ("builtin", ["10:00"], {I}),
    "imaging.scr_interval": ("builtin", 300.0, {I}),
    "imaging.panel_colour_scale": ("builtin", "per_panel", {I}),
    "imaging.samples_per_pixel_side": ("builtin", 32, {I}),
    "imaging.sensor.preset": ("builtin", "sdgsat1_tis", {I}),
    "imaging.sensor.response_file": ("builtin", None, {I}),    # with preset = 'user' below
    "imaging.sensor.altitude_m": ("builtin", 700.0e3, {I}),
    "imaging.sensor.focal_length_m": ("builtin", 1.2, {I}),
    "imaging.sensor.aperture_m": ("builtin", 0.4, {I}),
    "imaging.sensor.pixel_pitch_m": ("builtin", 30e-6, {I}),
    "imaging.sensor.optics_transmittance": ("builtin", 0.6, {I}),
    "imaging.sensor.view_zenith_deg": ("builtin", 20.0, {I}),
    "imaging.sensor.view_azimuth_deg": ("builtin", 45.0, {I}),
    "imaging.sensor.psf": ("builtin", True, {I}),
    "imaging.sensor.netd_k": ("builtin", 0.05, {I}),
    "imaging.sensor.quantisation_bits": ("builtin", 12, {I}),   # refused by the wiring
    "imaging.atmosphere.backend": ("builtin", "lowtran", {I}),
    "imaging.atmosphere.model": ("builtin", "winter", {I}),
    "calendar.satellites": ("builtin", ["landsat9"], {C}),
    "calendar.tle": ("cal_swath", "sat.tle", {C}),
    "calendar.swath": ("builtin", 250000.0, {C}),
    "calendar.times": ("builtin", ["2023-07-15T02:30:00Z"], {C}),
    "calendar.threshold": ("builtin", 2.0, {C}),
    "calendar.dense_step": ("builtin", 1800.0, {C}),
    "calendar.years": ("builtin", [2022, 2023], {C}),
    "calendar.year_sources": ("cal_years", ["a.epw"], {C}),
    "imaging.atmosphere.cloud_type": ("builtin", "stratus", {I}),
    "outputs.directory": ("builtin", "runs/elsewhere", {O}),
    "outputs.formats": ("builtin", ["csv"], {O}),
    "outputs.figure_dpi": ("builtin", 300, {O}),
    "outputs.checkpoint_interval": ("builtin", 7200.0, {T}),
}

#: Keys that reach no stage, and why (findings, not failures)
REACHES_NO_STAGE = {
    "description": "free text: written with the run's scenario copy only",
    "weather.year": "a typical-year file's year; the only accepted value is the year of "
                    "time.date (checked at load), which already sets it",
    "ship.files.clean": "mesh reading: a clean file is the same after cleaning",
    "ship.files.fix_normals": "mesh reading: a consistently wound file is unchanged",
    "ship.files.repair": "mesh reading: a watertight file needs no repair",
    "ship.files.repair_edge_length": "mesh reading: only with a repair",
    "ship.files.max_repair_change": "mesh reading: a check on a repair's change",
    "ship.files.check_scale": "mesh reading: a check on the length (units)",
    "weather.max_site_distance": "a check of a typical-year file's station against "
                                 "[location]; the record it lets through is unchanged",
    "background.water_vapour": "the overpass LST of `shipthermal background` for a Level-1 "
                               "scene without a met grid; the hourly background takes the met "
                               "grid's water vapour",
}


def _layup(material="mild_steel", thickness=0.008, cells=2):
    return [{"material": "deck_covering", "thickness": 0.003, "cells": 1},
            {"material": material, "thickness": thickness, "cells": cells}]


def _change(key: str, base: dict, value, d: Path) -> dict:
    """The base scenario with ``key`` set to ``value`` (placeholders filled)."""
    data = _merge(base)
    if key == "ship.files.mesh":        # per-part files → the same ship as one mesh
        data["ship"]["files"] = {"mesh": "boat.ply", "part_map": "boat_parts.json",
                                 "units": "m"}
        return data
    if key == "ship.files.parts.<part>":
        data["ship"]["files"]["parts"]["deck"] = "boat_parts/deck_moved.stl"
        return data
    if key == "background.source":
        data["background"] = bases(d)["bg_files"]["background"]
        return data
    if key == "imaging.sensor.response_file":   # a user sensor: its band's response table
        f = d / "user_band.csv"
        f.write_text("wavelength_um,response\n10.0,0\n10.5,1\n11.5,1\n12.0,0\n")
        data.setdefault("imaging", {})["sensor"] = {"preset": "user", "response_file": str(f)}
        return data
    if key.startswith("background.") and value is None:      # another file of that kind
        name = key.split(".")[1]
        src = Path(data["background"][name])
        copy = d / f"other_{src.name}"
        if not copy.exists():
            shutil.copy(src, copy)
            if name == "mtl":                # band files are found next to the MTL
                for f in PORT.glob("LC08_*.TIF"):
                    shutil.copy(f, d / f.name)
        data["background"][name] = str(copy)
        return data
    if key.startswith("ship.layups"):
        layers = {"ship.layups.<part>": _layup(cells=3, thickness=0.010),
                  "ship.layups.<part>[i].material": _layup(material="aluminium_5083"),
                  "ship.layups.<part>[i].thickness": _layup(thickness=0.012),
                  "ship.layups.<part>[i].cells": _layup(cells=4),
                  "ship.layups.<part>[i].solar_absorptivity": [
                      {"material": "marine_paint", "thickness": 0.0003, "solar_absorptivity": 0.95},
                      {"material": "mild_steel", "thickness": 0.008}],
                  "ship.layups.<part>[i].longwave_emissivity": [
                      {"material": "marine_paint", "thickness": 0.0003, "longwave_emissivity": 0.8},
                      {"material": "mild_steel", "thickness": 0.008}]}[key]
        data["ship"]["layups"] = {FUNNEL: layers}
        return data
    if key.startswith("materials."):
        data["materials"]["own"][key.rsplit(".", 1)[1]] = value
        return data
    path = key.split(".<")[0].split(".")
    node = data
    for p in path[:-1]:
        node = node.setdefault(p, {})
    if "<" in key:                       # a per-part table: value is {part: ...}
        node[path[-1]] = _merge(node.get(path[-1], {}), value)
    elif value is None:
        node.pop(path[-1], None)
    else:
        node[path[-1]] = value
    return data


# ---------------------------------------------------------------------------------------
# what each stage receives, as comparable plain data
# ---------------------------------------------------------------------------------------
def _plain(x):
    if isinstance(x, np.ndarray):
        return ("array", x.shape, str(x.dtype), x.tobytes())
    if isinstance(x, (pd.DatetimeIndex, pd.Index)):
        return ("index", str(x.dtype), tuple(x.astype(str)))
    if isinstance(x, pd.Timestamp):
        return ("time", str(x))
    if dataclasses.is_dataclass(x) and not isinstance(x, type):
        return (type(x).__name__,) + tuple((f.name, _plain(getattr(x, f.name)))
                                           for f in dataclasses.fields(x))
    if isinstance(x, dict) or hasattr(x, "items"):
        return tuple(sorted((str(k), _plain(v)) for k, v in x.items()))
    if isinstance(x, (list, tuple)):
        return tuple(_plain(v) for v in x)
    if isinstance(x, (str, int, float, bool, type(None), np.floating, np.integer)):
        return x
    return (type(x).__name__, _plain(vars(x)))


def _environment(env):
    w = env.weather
    span = 86400.0 if w.periodic else (w.time[-1] - env.start).total_seconds() + 1.0
    st = env.at(np.arange(0.0, span, 1800.0))
    keep = {k: v for k, v in vars(env).items() if k not in ("weather",)}
    return _plain({"state": st, "env": keep, "periodic": w.periodic})


#: What the physical background takes of the environment (the ship's motion and the sea's
#: emissivity belong to the thermal stage alone)
BACKGROUND_STATE = ("zenith", "azimuth", "dni", "dhi", "ghi", "temp_air", "relative_humidity",
                    "longwave_down", "wind_speed", "temp_sea", "temp_sea_skin")


def _background(given):
    kind, kwargs = given
    env = kwargs.get("environment")
    if env is None:
        return _plain(given)
    w = env.weather
    span = 86400.0 if w.periodic else (w.time[-1] - env.start).total_seconds() + 1.0
    st = env.at(np.arange(0.0, span, 1800.0))
    used = {k: getattr(st, k) for k in BACKGROUND_STATE if hasattr(st, k)}
    rest = {k: v for k, v in kwargs.items() if k != "environment"}
    return _plain((kind, {**rest, "state": used, "altitude": env.altitude,
                          "start": env.start}))


def _ship(ship):
    return _plain({k: getattr(ship, k) for k in ("vertices", "faces", "face_part", "part_names",
                                                  "layups", "compartment_temperature",
                                                  "outer_medium")})


_SHIPS: dict = {}


def _build_ship(sc):
    # ``sc.ship()`` is a method of the [ship] section: it can only depend on that section
    key = repr(_plain(sc.ship))
    if key not in _SHIPS:
        _SHIPS[key] = sc.ship()
    return _SHIPS[key]


def _safe(f):
    try:
        return f()
    except InputError as exc:
        return ("refused", str(exc))


def stage_inputs(sc, background, ship) -> dict:
    def thermal():
        given = thermal_inputs(sc, _build_ship(sc))
        return {"ship": _ship(given.pop("ship")), "environment": _environment(
            given.pop("environment")), **{k: _plain(v) for k, v in given.items()}}

    def imaging():
        check_imaging_bands(sc)
        img = imaging_scenario(sc, background, ship)
        fields = {f.name: getattr(img, f.name) for f in dataclasses.fields(img)
                  if f.name != "background"}
        return _plain({**fields, "experiment": experiment_inputs(sc)})

    return {T: _safe(thermal), B: _safe(lambda: _background(background_inputs(sc))),
            C: _safe(lambda: _plain(calendar_inputs(sc))),
            I: _safe(imaging), O: _safe(lambda: _plain(output_inputs(sc)))}


@pytest.fixture(scope="module")
def baselines(files, background, ship):
    return {name: stage_inputs(load_scenario(data, base_dir=files), background, ship)
            for name, data in bases(files).items()}


def _leaf_keys():
    return [k for k in schema_keys() if not k.startswith("[")]


def test_every_key_is_listed():
    keys = set(_leaf_keys())
    assert keys == set(CASES), (f"not listed: {sorted(keys - set(CASES))}; "
                                f"not keys: {sorted(set(CASES) - keys)}")
    assert set(REACHES_NO_STAGE) == {k for k, v in CASES.items() if not v[2]}


def test_the_bases_build(baselines):
    for name, stages in baselines.items():
        refused = {s for s, v in stages.items() if isinstance(v, tuple) and v[:1] == ("refused",)}
        allowed = {"record": {I}}.get(name, set())
        assert refused <= allowed, (name, {s: stages[s] for s in refused - allowed})


@pytest.mark.parametrize("key", sorted(CASES))
def test_key_reaches_its_stages(key, files, background, ship, baselines):
    base_name, value, expected = CASES[key]
    data = _change(key, bases(files)[base_name], value, files)
    sc = load_scenario(data, base_dir=files)
    now = stage_inputs(sc, background, ship)
    before = baselines[base_name]
    reached = {s for s in now if now[s] != before[s]}
    assert reached == expected, (f"{key} = {value!r} reaches {sorted(reached)}, "
                                 f"expected {sorted(expected)}")
