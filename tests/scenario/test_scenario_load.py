"""Loading, defaults, examples, round trip and laziness of the scenario file."""

import dataclasses
import os
import subprocess
import sys
import textwrap
import tomllib
from pathlib import Path

import pytest

from shipthermal.errors import InputError
from shipthermal.app.scenario import (SEASONS, Scenario, ScenarioError, clock_seconds,
                                  default_scenario, example_path, load_scenario,
                                  loads_scenario, parse_band)


@pytest.mark.parametrize("season", SEASONS)
def test_example_file_equals_default(season):
    # The commented examples claim to show the defaults: they must load to exactly the
    # default scenario (description aside), so a drifting default or example fails here.
    sc = load_scenario(example_path(season))
    assert sc.description.startswith(f"Built-in {season} day")
    assert dataclasses.replace(sc, description="") == default_scenario(season)
    assert sc.time.season == season
    assert sc.source == str(example_path(season))


def test_season_defaults():
    s, w = default_scenario("summer"), default_scenario("winter")
    assert (s.time.date, w.time.date) == ("2023-07-15", "2023-01-15")
    assert s.name == "summer" and s.outputs.directory == "runs/summer"
    # ISO 7547 indoor design: 27 degC summer, 22 degC winter
    assert s.ship.compartment_temperature_of("deck") == pytest.approx(300.15, abs=1e-12)
    assert w.ship.compartment_temperature_of("hull_wetted") == pytest.approx(295.15, abs=1e-12)
    assert s.time.map_times == ("07:00", "12:00") and w.time.map_times == ("08:00", "12:00")
    assert w.imaging.times == ("00:00", "08:30", "12:00", "18:30")
    assert s.atmosphere_season == "summer" and w.atmosphere_season == "winter"


@pytest.mark.parametrize("season", SEASONS)
def test_round_trip_toml(season, tmp_path):
    sc = load_scenario(example_path(season))
    again = loads_scenario(sc.to_toml())
    assert again == sc
    # the text is real TOML and the written copy loads back identically
    assert tomllib.loads(sc.to_toml())["time"]["season"] == season
    path = sc.write(tmp_path / "run" / "scenario.toml")
    assert load_scenario(path) == sc
    # atomic write: nothing but the target is left in the folder
    assert sorted(p.name for p in path.parent.iterdir()) == ["scenario.toml"]


def test_round_trip_non_default_values(tmp_path):
    (tmp_path / "w.epw").write_text("")
    text = textwrap.dedent("""
        name = "trial-1"
        [location]
        latitude = 36.07
        longitude = 120.38
        time_zone = "Asia/Shanghai"
        [time]
        season = "winter"
        date = 2022-12-20
        output_interval = 900
        map_times = ["09:15"]
        [weather]
        source = "w.epw"
        temp_sea = 280.0
        year = 2022
        day = "record"
        use_measured_longwave = false
        [ship]
        builtin = "patrol_boat"
        edge_length = 1.5
        heading = 45.5
        speed = 6.0
        mooring_position = [-100, 250.5]
        [ship.parameters]
        length = 60.0
        [ship.layups]
        deck = [{material = "deck_covering", thickness = 0.004},
                {material = "mild_steel", thickness = 0.012, cells = 3}]
        [ship.compartment_temperature]
        superstructure_mast = 280.0
        [ship.band_emissivity.hull]
        "3.7-4.8" = 0.8
        [solver]
        time_step = 900
        scheme = "crank_nicolson"
        [imaging]
        bands = ["mwir", "3.7-4.8", [8.0, 12.0]]
        [imaging.atmosphere]
        model = "summer"
        [outputs]
        formats = []
        checkpoint_interval = 0
    """)
    sc = loads_scenario(text, base_dir=tmp_path)
    assert sc.imaging.bands == ("3-5", "3.7-4.8", "8-12")
    assert sc.ship.layups["deck"][0].cells == 1
    assert sc.weather.source == (tmp_path / "w.epw").resolve().as_posix()
    assert loads_scenario(sc.to_toml()) == sc
    assert load_scenario(sc.to_dict()) == sc


def test_relative_paths_resolve_against_the_file(tmp_path):
    (tmp_path / "data").mkdir()
    (tmp_path / "data" / "w.csv").write_text("time,temp_air\n")
    (tmp_path / "cases").mkdir()
    f = tmp_path / "cases" / "a.toml"
    f.write_text('[weather]\nsource = "../data/w.csv"\n')
    sc = load_scenario(f)
    assert Path(sc.weather.source) == (tmp_path / "data" / "w.csv").resolve()
    # the same relative path from another folder is a missing file, named as such
    with pytest.raises(ScenarioError, match="weather.source"):
        load_scenario({"weather": {"source": "../data/w.csv"}}, base_dir=tmp_path)


def test_updated_revalidates():
    sc = default_scenario("summer")
    turned = sc.updated({"ship.heading": 90, "weather.wind_speed_offset": 1.0})
    assert turned.ship.heading == 90.0 and turned.weather.wind_speed_offset == 1.0
    assert dataclasses.replace(turned, ship=sc.ship, weather=sc.weather) == sc
    with pytest.raises(ScenarioError, match=r"ship\.speed = -1"):
        sc.updated({"ship.speed": -1})


def test_frozen():
    sc = default_scenario("summer")
    with pytest.raises(dataclasses.FrozenInstanceError):
        sc.ship.heading = 3.0
    with pytest.raises(TypeError):
        sc.ship.solar_absorptivity["deck"] = 0.1


def test_load_is_lazy():
    # Loading must not import the heavy stages (pandas, pvlib, scipy, imaging, meshing): a
    # fresh interpreter imports the module and validates the summer example. Of the imaging
    # package only its parameter module (which imports only the named bands) may be loaded.
    # (Its time is measured in benchmarks/, not asserted here.)
    code = textwrap.dedent("""
        import sys
        from shipthermal.app.scenario import load_scenario, example_path
        load_scenario(example_path("summer"))
        heavy = [m for m in ("pandas", "pvlib", "scipy", "trimesh", "pyvista",
                             "embreex", "manifold3d", "numba") if m in sys.modules]
        heavy += sorted(m for m in sys.modules if m.startswith("imaging.")
                        and m != "imaging.parameters")
        print(",".join(heavy))
    """)
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True).stdout.strip()
    assert out == "", f"heavy modules imported at load: {out}"


def test_not_a_file_and_bad_toml(tmp_path):
    with pytest.raises(ScenarioError, match="must be an existing TOML file"):
        load_scenario(tmp_path / "nope.toml")
    f = tmp_path / "bad.toml"
    f.write_text("[ship]\nheading = \n")
    with pytest.raises(ScenarioError, match=r"must be valid TOML .*line 2"):
        load_scenario(f)


def test_scenario_error_is_input_error_with_all_problems():
    bad = {"location": {"latitude": 99.0, "longitud": 121.0},
           "ship": {"speed": -3.0, "heading": 400.0},
           "solver": {"time_step": 0.0},
           "imaging": {"bands": ["3-5", "15-20"]}}
    with pytest.raises(InputError) as info:
        load_scenario(bad)
    err = info.value
    assert isinstance(err, ScenarioError)
    fields = [e.field for e in err.errors]
    assert fields == ["location.latitude", "location.longitud", "ship.speed", "ship.heading",
                      "solver.time_step", "imaging.bands[1]"]
    assert all(isinstance(e, InputError) for e in err.errors)
    # one line per problem in the message, first problem exposed as the error's own field
    assert str(err).count("\n  - ") == 6 and err.field == "location.latitude"
    assert "Did you mean 'longitude'?" in str(err)


def test_default_scenario_rejects_unknown_season():
    with pytest.raises(InputError, match="season"):
        default_scenario("spring")


def test_clock_and_band_helpers():
    assert clock_seconds("07:30") == 27000.0
    assert default_scenario("winter").image_seconds() == (0.0, 30600.0, 43200.0, 66600.0)
    assert parse_band("LWIR") == ("8-14", (8.0, 14.0))
    assert parse_band([3, 5]) == ("3-5", (3.0, 5.0))
    assert parse_band("3.7-4.8um") == ("3.7-4.8", (3.7, 4.8))
    for bad in ("2-5", "5-3", "8-15", "x", [1], True):
        with pytest.raises(InputError):
            parse_band(bad)


def test_dict_input_uses_cwd_for_relative_paths(tmp_path, monkeypatch):
    (tmp_path / "w.csv").write_text("")
    monkeypatch.chdir(tmp_path)
    sc = load_scenario({"weather": {"source": "w.csv", "temp_sea": 290.0}})
    assert os.path.samefile(sc.weather.source, tmp_path / "w.csv")
    assert isinstance(sc, Scenario)
