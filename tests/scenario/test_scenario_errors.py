"""Catalogue of bad scenario inputs: each gives exactly one error naming the key's dotted
path, the value and what is allowed — and nothing is written."""

import json

import pytest

from shipthermal.errors import InputError
from shipthermal.app.scenario import ScenarioError, load_scenario, loads_scenario


def _files(tmp):
    """Input files the cases point at (contents are not read at load, except the JSON)."""
    for name in ("weather.dat", "w.csv", "w.epw", "ship.stl", "hull.stl", "deck.stl",
                 "scene_MTL.txt", "dem.tif"):
        (tmp / name).write_text("")
    (tmp / "ship_parts.json").write_text(json.dumps(
        {"parts": {"hull": [[0, 10]], "deck": [[10, 20]], "superstructure_radar": [[20, 30]]}}))
    (tmp / "bad_parts.json").write_text(json.dumps({"parts": {"funnel": [[0, 10]]}}))


# (id, scenario dict, dotted path of the one error, fragments the message must contain:
#  the allowed values / range and, where given, the fix)
CASES = [
    # ---- location -------------------------------------------------------------------------
    ("lat-range", {"location": {"latitude": 95.0}}, "location.latitude",
     ["= 95.0", "must lie in [-66, 66] deg"]),
    ("lat-type", {"location": {"latitude": "38.9"}}, "location.latitude",
     ["'38.9'", "must be a number in [-66, 66] deg", "without quotes"]),
    ("lon-range", {"location": {"longitude": 200}}, "location.longitude",
     ["must lie in [-180, 180] deg"]),
    ("tz-unknown", {"location": {"time_zone": "Mars/Olympus"}}, "location.time_zone",
     ["IANA time-zone name", "Etc/GMT-8"]),
    ("altitude-nan", {"location": {"altitude": float("nan")}}, "location.altitude",
     ["must be a finite number in [-500, 9000] m"]),
    ("unknown-key", {"location": {"lattitude": 38.0}}, "location.lattitude",
     ["unknown key", "latitude, longitude, time_zone, altitude", "Did you mean 'latitude'?"]),
    ("unknown-section", {"imagin": {"bands": ["3-5"]}}, "imagin",
     ["unknown key", "Did you mean 'imaging'?"]),
    ("section-not-table", {"weather": "builtin"}, "weather", ["must be a table"]),
    ("builtin-far-from-dalian", {"location": {"latitude": 50.0}}, "location.latitude",
     ["within 3 deg of Dalian", "give its weather record", "docs/WEATHER.md", "day = \"record\""]),
    # ---- time -----------------------------------------------------------------------------
    ("date-not-a-day", {"time": {"date": "2023-02-30"}}, "time.date",
     ["calendar date YYYY-MM-DD"]),
    ("date-out-of-season", {"time": {"date": "2023-01-15"}}, "time.date",
     ["months [6, 7, 8]", "built-in summer design day"]),
    ("season-unknown", {"time": {"season": "autumn"}}, "time.season",
     ["one of 'summer', 'winter'"]),
    ("output-interval-zero", {"time": {"output_interval": 0}}, "time.output_interval",
     ["must lie in (0, 86400] s"]),
    ("output-interval-vs-step", {"time": {"output_interval": 1200},
                                 "solver": {"time_step": 900}}, "time.output_interval",
     ["multiple of solver.time_step (900 s)"]),
    ("map-time-25h", {"time": {"map_times": ["07:00", "25:00"]}}, "time.map_times[1]",
     ["'HH:MM' (00:00-23:59)"]),
    # ---- weather --------------------------------------------------------------------------
    ("weather-missing-file", {"weather": {"source": "nowhere.csv"}}, "weather.source",
     ["must be an existing file", "relative to the scenario file"]),
    ("weather-unknown-extension", {"weather": {"source": "weather.dat"}}, "weather.format",
     ["cannot tell the format", "'.dat'", "'ndbc'", "docs/WEATHER.md"]),
    ("weather-days-without-record", {"weather": {"source": "w.csv", "days": 3}},
     "weather.days", ["only applies with weather.day = 'record'"]),
    ("weather-days-too-many", {"weather": {"source": "w.csv", "day": "record", "days": 401}},
     "weather.days", ["must lie in [1, 400]"]),
    ("weather-wind-height", {"weather": {"source": "w.csv", "wind_height": 0.0}},
     "weather.wind_height", ["must lie in [0.1, 300] m"]),
    ("weather-cloud-constant", {"weather": {"source": "w.csv", "cloud_cover": 8}},
     "weather.cloud_cover", ["must lie in [0, 1]"]),
    ("weather-key-on-builtin", {"weather": {"wind_height": 5.0}}, "weather.wind_height",
     ["only applies to a weather file"]),
    ("clear-sky-typo", {"weather": {"clear_sky_model": "brutsart"}}, "weather.clear_sky_model",
     ["one of 'brutsaert', 'prata', 'swinbank'", "Did you mean 'brutsaert'?"]),
    ("cloud-model", {"weather": {"cloud_model": "kasten"}}, "weather.cloud_model",
     ["'crawford_duchon', 'unsworth_monteith'"]),
    ("file-option-on-builtin", {"weather": {"temp_sea": 290.0}}, "weather.temp_sea",
     ["only applies to a weather file"]),
    ("epw-needs-sst", {"weather": {"source": "w.epw"}}, "weather.temp_sea",
     ["required for EPW", "[269, 310] K"]),
    ("tmy3-leap-year", {"weather": {"source": "w.csv", "format": "tmy3", "temp_sea": 290.0,
                                    "year": 2004}}, "weather.year", ["must not be a leap year"]),
    ("weather-year-vs-date", {"weather": {"source": "w.epw", "temp_sea": 290.0,
                                          "year": 2021}}, "weather.year",
     ["must equal the year of time.date (2023)"]),
    ("tmy3-leap-date", {"weather": {"source": "w.csv", "format": "tmy3", "temp_sea": 290.0},
                        "time": {"date": "2024-07-15"}}, "time.date", ["leap year", "TMY3"]),
    ("sea-emissivity", {"weather": {"sea_emissivity": 1.2}}, "weather.sea_emissivity",
     ["[0.5, 1]"]),
    # ---- ship -----------------------------------------------------------------------------
    ("negative-speed", {"ship": {"speed": -2.0}}, "ship.speed", ["= -2.0", "[0, 30] m/s"]),
    ("heading-360", {"ship": {"heading": 360}}, "ship.heading", ["[0, 360) deg"]),
    ("builtin-unknown", {"ship": {"builtin": "destroyer"}}, "ship.builtin",
     ["'cargo_ship', 'frigate', 'patrol_boat'"]),
    ("absorptivity-zero", {"ship": {"solar_absorptivity": {"deck": 0.0}}},
     "ship.solar_absorptivity.deck", ["(0, 1]"]),
    ("lw-emissivity-above-1", {"ship": {"longwave_emissivity": {"hull": 1.05}}},
     "ship.longwave_emissivity.hull", ["= 1.05", "(0, 1]"]),
    ("band-emissivity-negative", {"ship": {"band_emissivity": {"superstructure": {"3-5": -0.1}}}},
     "ship.band_emissivity.superstructure.3-5", ["(0, 1]"]),
    ("band-emissivity-band", {"ship": {"band_emissivity": {"deck": {"2-5": 0.9}}}},
     "ship.band_emissivity.deck.2-5", ["2.9 <= lo < hi <= 14.5"]),
    ("layer-thickness", {"ship": {"layups": {"deck": [
        {"material": "deck_covering", "thickness": 0.003},
        {"material": "mild_steel", "thickness": -0.01}]}}},
     "ship.layups.deck[1].thickness", ["= -0.01", "(0, 1] m"]),
    ("layer-material", {"ship": {"layups": {"hull": [{"material": "steel", "thickness": 0.01}]}}},
     "ship.layups.hull[0].material", ["'mild_steel'", "Did you mean 'mild_steel'?",
                                      "add [materials.steel]"]),
    ("layer-own-material", {"materials": {"plate": {"conductivity": 50.0, "density": 7850.0,
                                                    "specific_heat": 470.0, "source": "s"}},
                            "ship": {"layups": {"deck": [{"material": "plates",
                                                          "thickness": 0.01}]}}},
     "ship.layups.deck[0].material", ["'plate'", "'mild_steel'", "Did you mean 'plate'?"]),
    ("layer-zero-thickness", {"ship": {"layups": {"hull": [{"material": "mild_steel",
                                                            "thickness": 0.0}]}}},
     "ship.layups.hull[0].thickness", ["= 0.0", "(0, 1] m", "in metres"]),
    ("material-without-k", {"materials": {"plate": {"density": 7850.0, "specific_heat": 470.0,
                                                    "source": "mill certificate"}}},
     "materials.plate.conductivity", ["is required", "[0.001, 500] W m-1 K-1",
                                      "specific_heat"]),
    ("material-k-unit", {"materials": {"plate": {"conductivity": 50000.0, "density": 7850.0,
                                                 "specific_heat": 470.0, "source": "s"}}},
     "materials.plate.conductivity", ["= 50000.0", "[0.001, 500]", "W m-1 K-1"]),
    ("material-builtin-name", {"materials": {"mild_steel": {
        "conductivity": 50.0, "density": 7850.0, "specific_heat": 470.0, "source": "s"}}},
     "materials.mild_steel", ["built-in", "mild_steel_own"]),
    ("paint-inner-layer", {"ship": {"layups": {"deck": [
        {"material": "mild_steel", "thickness": 0.01},
        {"material": "marine_paint", "thickness": 0.0003, "solar_absorptivity": 0.9}]}}},
     "ship.layups.deck[1].solar_absorptivity", ["outer layer only", "ship.layups.deck[0]"]),
    ("paint-given-twice", {"ship": {"layups": {"deck": [
        {"material": "marine_paint", "thickness": 0.0003, "longwave_emissivity": 0.9},
        {"material": "mild_steel", "thickness": 0.01}]}, "longwave_emissivity": {"deck": 0.8}}},
     "ship.longwave_emissivity.deck", ["given twice", "Keep one"]),
    ("convection-part-model", {"convection": {"parts": {"deck": "doe-2"}}},
     "convection.parts.deck", ["'doe2'", "'flat_plate_turbulent'", "Did you mean 'doe2'?"]),
    ("convection-roughness", {"convection": {"roughness": {"deck": "grit"}}},
     "convection.roughness.deck", ["'medium_rough'", "'very_smooth'"]),
    ("layer-cells", {"ship": {"layups": {"hull": [{"material": "mild_steel", "thickness": 0.01,
                                                   "cells": 2.5}]}}},
     "ship.layups.hull[0].cells", ["must be an integer in [1, 50]"]),
    ("layer-missing-material", {"ship": {"layups": {"deck": [{"thickness": 0.01}]}}},
     "ship.layups.deck[0].material", ["is required", "'mild_steel'"]),
    ("layup-bad-part-name", {"ship": {"layups": {"funnel": [{"material": "mild_steel",
                                                             "thickness": 0.01}]}}},
     "ship.layups.funnel", ["unknown part", "superstructure_funnel"]),
    ("part-not-on-ship", {"ship": {"compartment_temperature": {"superstructure_radar": 290.0}}},
     "ship.compartment_temperature.superstructure_radar",
     ["not a part of this ship", "superstructure_mast"]),
    ("compartment-in-celsius", {"ship": {"compartment_temperature": {"deck": 22.0}}},
     "ship.compartment_temperature.deck", ["[200, 400] K"]),
    ("beam-too-wide", {"ship": {"parameters": {"beam": 80.0}}}, "ship.parameters.beam",
     ["below half the length (66 m)", "frigate"]),
    ("length-range", {"ship": {"parameters": {"length": 600.0}}}, "ship.parameters.length",
     ["[5, 500] m"]),
    ("edge-length-vs-ship", {"ship": {"edge_length": 20.0}}, "ship.edge_length",
     ["[0.0132, 13.2] m for a 132 m ship"]),
    ("mooring-outside-port", {"ship": {"mooring_position": [6000.0, 0.0]}},
     "ship.mooring_position", ["inside the port scene", "5010 m"]),
    ("mooring-shape", {"ship": {"mooring_position": [1.0]}}, "ship.mooring_position",
     ["[x, y], two finite numbers [m]"]),
    ("files-without-units", {"ship": {"files": {"mesh": "ship.stl",
                                                "part_map": "ship_parts.json"}}},
     "ship.files.units", ["'m' or 'mm'"]),
    ("files-mesh-and-parts", {"ship": {"files": {"units": "m", "mesh": "ship.stl",
                                                 "part_map": "ship_parts.json",
                                                 "parts": {"hull": "hull.stl"}}}},
     "ship.files", ["exactly one of 'mesh'"]),
    ("files-stl-needs-part-map", {"ship": {"files": {"units": "m", "mesh": "ship.stl"}}},
     "ship.files.part_map", ["only VTK/VTP/VTU"]),
    ("files-part-map-names", {"ship": {"files": {"units": "mm", "mesh": "ship.stl",
                                                 "part_map": "bad_parts.json"}}},
     "ship.files.part_map['funnel']", ["unknown part"]),
    ("files-missing-part-file", {"ship": {"files": {"units": "m", "parts": {
        "hull": "hull.stl", "deck": "nothere.stl"}}}},
     "ship.files.parts.deck", ["must be an existing file"]),
    ("builtin-and-files", {"ship": {"builtin": "frigate", "files": {
        "units": "m", "parts": {"hull": "hull.stl", "deck": "deck.stl"}}}},
     "ship.builtin", ["either builtin or [ship.files]"]),
    # ---- solver -----------------------------------------------------------------------------
    ("time-step-zero", {"solver": {"time_step": 0.0}}, "solver.time_step",
     ["= 0.0", "(0, 3600] s"]),
    ("time-step-too-long", {"solver": {"time_step": 7200}}, "solver.time_step",
     ["(0, 3600] s"]),
    ("time-step-not-dividing-day", {"solver": {"time_step": 7.0}}, "solver.time_step",
     ["must divide 24 h"]),
    ("scheme", {"solver": {"scheme": "rk4"}}, "solver.scheme",
     ["'backward_euler', 'crank_nicolson', 'bdf2'"]),
    ("spinup-days", {"solver": {"spinup_max_days": 0}}, "solver.spinup_max_days",
     ["[1, 100]"]),
    ("seed-bool", {"solver": {"seed": True}}, "solver.seed", ["must be an integer"]),
    # ---- background -------------------------------------------------------------------------
    ("background-files-incomplete", {"background": {"source": "files", "mtl": "scene_MTL.txt",
                                                    "dem": "dem.tif", "met": "dem.tif"}},
     "background.roi", ["required with source = 'files'"]),
    ("background-file-on-builtin", {"background": {"dem": "dem.tif"}}, "background.dem",
     ["only applies with source = 'files'"]),
    # ---- imaging ----------------------------------------------------------------------------
    ("band-below-tables", {"imaging": {"bands": ["3-5", "1-2"]}}, "imaging.bands[1]",
     ["2.9 <= lo < hi <= 14.5", "atmosphere tables"]),
    ("band-above-tables", {"imaging": {"bands": [[8.0, 16.0]]}}, "imaging.bands[0]",
     ["2.9 <= lo < hi <= 14.5"]),
    ("band-without-emissivity", {"imaging": {"bands": ["5-8"]}}, "ship.band_emissivity",
     ["imaging band '5-8' for hull, deck, superstructure", "[ship.band_emissivity.hull]"]),
    ("samples-per-pixel", {"imaging": {"samples_per_pixel_side": 8}},
     "imaging.samples_per_pixel_side", ["[16, 256]"]),
    ("optics-transmittance", {"imaging": {"sensor": {"optics_transmittance": 0.0}}},
     "imaging.sensor.optics_transmittance", ["(0, 1]"]),
    ("view-zenith-table", {"imaging": {"sensor": {"view_zenith_deg": 83.0}}},
     "imaging.sensor.view_zenith_deg", ["[0, 80] deg with the 'table'"]),
    ("atmosphere-backend", {"imaging": {"atmosphere": {"backend": "modtran"}}},
     "imaging.atmosphere.backend", ["'table', 'lowtran'"]),
    ("scr-interval", {"imaging": {"scr_interval": 1800.0}}, "imaging.scr_interval",
     ["(0, 600] s"]),
    # ---- outputs / top level ------------------------------------------------------------------
    ("output-format", {"outputs": {"formats": ["png", "docx"]}}, "outputs.formats[1]",
     ["'csv', 'geotiff'"]),
    ("checkpoint-vs-step", {"outputs": {"checkpoint_interval": 1000.0}},
     "outputs.checkpoint_interval", ["multiple of solver.time_step (300 s)"]),
    ("name", {"name": "my run"}, "name", ["letters, digits, _ . -"]),
]


@pytest.mark.parametrize("case,data,path,fragments", CASES, ids=[c[0] for c in CASES])
def test_bad_input(case, data, path, fragments, tmp_path):
    _files(tmp_path)
    before = sorted(p.name for p in tmp_path.iterdir())
    with pytest.raises(ScenarioError) as info:
        load_scenario(data, base_dir=tmp_path)
    err = info.value
    # exactly one problem, so one mistake gives one message (no cascade of consequences)
    assert [e.field for e in err.errors] == [path], str(err)
    one = err.errors[0]
    assert isinstance(one, InputError)
    text = str(one)
    assert text.startswith(f"{path} = "), text       # the key's dotted path and its value
    for frag in fragments:
        assert frag in text, f"{frag!r} not in {text!r}"
    assert str(err).endswith(text)                    # listed in the combined message
    assert sorted(p.name for p in tmp_path.iterdir()) == before   # nothing written


def test_all_errors_of_a_file_in_one_pass(tmp_path):
    _files(tmp_path)
    merged = {}
    chosen = [c for c in CASES if c[0] in (
        "lat-range", "tz-unknown", "negative-speed", "layer-thickness", "time-step-zero",
        "band-below-tables", "view-zenith-table", "weather-missing-file", "name")]
    for _, data, _, _ in chosen:
        for key, val in data.items():
            if isinstance(val, dict):
                merged.setdefault(key, {}).update(val)
            else:
                merged[key] = val
    with pytest.raises(ScenarioError) as info:
        load_scenario(merged, base_dir=tmp_path)
    assert sorted(e.field for e in info.value.errors) == sorted(c[2] for c in chosen)


def test_toml_text_errors_name_the_path(tmp_path):
    text = """
[ship]
speed = -1.5
[[ship.layups.deck]]
material = "deck_covering"
thickness = 0.003
[[ship.layups.deck]]
material = "mild_steel"
thickness = "10 mm"
"""
    with pytest.raises(ScenarioError) as info:
        loads_scenario(text, base_dir=tmp_path, source="case.toml")
    msg = str(info.value)
    assert msg.startswith("case.toml: 2 problems")
    assert "ship.speed = -1.5: must lie in [0, 30] m/s" in msg
    assert "ship.layups.deck[1].thickness = '10 mm': must be a number in (0, 1] m" in msg


def test_water_vapour_range_is_the_retrievals():
    """The scenario's copy of the single-channel LST's water-vapour range (written in the
    scenario values so that loading stays light) equals the retrieval's own."""
    from imaging.background.lst import WATER_VAPOUR_RANGE

    from shipthermal.app.scenario.values import WATER_VAPOUR_RANGE as copy

    assert copy == WATER_VAPOUR_RANGE
