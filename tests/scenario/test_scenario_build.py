"""The scenario's builders: environment, weather record, ship, emissivities, sensor."""

import dataclasses

import numpy as np
import pandas as pd
import pytest

from shipthermal.environment import Environment, climate_day
from shipthermal.errors import InputError
from shipthermal.app.scenario import (SEASONS, default_scenario, example_path, load_scenario)
from shipthermal.units import ZERO_CELSIUS


@pytest.mark.parametrize("season", SEASONS)
def test_example_environment_matches_scenario(season):
    sc = load_scenario(example_path(season))
    env = sc.environment()
    assert isinstance(env, Environment)
    assert env.latitude == sc.location.latitude and env.longitude == sc.location.longitude
    assert env.start == sc.start
    assert env.start.strftime("%Y-%m-%d") == sc.time.date
    assert str(env.start.tz) == sc.location.time_zone and env.start.hour == 0
    assert env.ship_heading == sc.ship.heading and env.ship_speed == sc.ship.speed
    assert env.clear_sky_model == sc.weather.clear_sky_model
    assert env.sea_emissivity == sc.weather.sea_emissivity
    assert env.sea_skin == sc.weather.sea_skin
    # The built-in weather is the climatology's design day, sample for sample (only the
    # site altitude differs: 0 m waterline vs the 92 m station, which enters the clear-sky
    # air mass, not the weather); with a skin model its SST is the daily mean (the warm
    # layer makes the diurnal cycle).
    ref = climate_day(season).weather(60, sst_cycle=sc.weather.sea_skin == "none")
    got = env.weather
    assert got.periodic
    for name in ("temp_air", "relative_humidity", "wind_speed", "wind_direction",
                 "cloud_cover", "temp_sea"):
        np.testing.assert_array_equal(getattr(got, name), getattr(ref, name), err_msg=name)
    # the clock: float seconds and the scenario's local instants give the same state
    state = env.at(np.array(sc.map_seconds()))
    inst = pd.DatetimeIndex([sc.start + pd.Timedelta(seconds=s) for s in sc.map_seconds()])
    np.testing.assert_array_equal(state.temp_air, env.at(inst).temp_air)
    assert [t.strftime("%H:%M") for t in state.times] == list(sc.time.map_times)


def test_builtin_offsets_shift_the_weather_exactly():
    base = default_scenario("summer").weather_record()
    moved = load_scenario({"weather": {"temp_air_offset": 1.0, "wind_speed_offset": -10.0,
                                       "cloud_cover_offset": 0.2}}).weather_record()
    # Parton-Logan is affine in (Tmin, Tmax): shifting both by 1 K shifts every hour by 1 K
    # (round-off only); wind is clipped at 0; cloud adds to the derived fraction.
    np.testing.assert_allclose(moved.temp_air - base.temp_air, 1.0, atol=1e-9)
    np.testing.assert_array_equal(moved.wind_speed, 0.0)
    np.testing.assert_allclose(moved.cloud_cover, np.clip(base.cloud_cover + 0.2, 0, 1), atol=1e-12)


def _write_csv(path, start="2024-07-14 00:00", hours=48):
    t = pd.date_range(start, periods=hours, freq="h")
    hour = np.arange(hours)
    df = pd.DataFrame({
        "time": t.strftime("%Y-%m-%dT%H:%M:%S"),
        "temp_air": 24.0 + 4.0 * np.sin(2 * np.pi * (hour - 9) / 24) + 0.01 * hour,
        "relative_humidity": 80.0,
        "wind_speed": 3.0 + 0.05 * hour,
        "wind_direction": 180.0,
        "cloud_cover": 0.4,
        "temp_sea": 23.0,
    })
    df.to_csv(path, index=False)
    return df


def test_csv_periodic_day_is_the_scenario_date(tmp_path):
    df = _write_csv(tmp_path / "w.csv")
    sc = load_scenario({"weather": {"source": "w.csv"}, "time": {"date": "2024-07-15"}},
                       base_dir=tmp_path)
    env = sc.environment()
    assert env.start == pd.Timestamp("2024-07-15 00:00", tz="Etc/GMT-8") == sc.start
    w = env.weather
    assert w.periodic and len(w.time) == 24
    # the file's second day, converted to kelvin, hour for hour (naive times are taken in
    # location.time_zone)
    np.testing.assert_allclose(w.temp_air, df["temp_air"].to_numpy()[24:] + ZERO_CELSIUS,
                               atol=1e-9)
    np.testing.assert_allclose(env.at(np.array([3600.0 * 5])).wind_speed,
                               df["wind_speed"].to_numpy()[29], atol=1e-12)


def test_csv_record_mode_and_coverage(tmp_path):
    df = _write_csv(tmp_path / "w.csv")
    sc = load_scenario({"weather": {"source": "w.csv", "day": "record",
                                    "temp_air_offset": -2.0},
                        "time": {"date": "2024-07-14"}}, base_dir=tmp_path)
    w = sc.weather_record()
    # two whole days, closing midnight included (the last hour held from 23:00, reported)
    assert not w.periodic and len(w.time) == 49 and w.start == sc.start
    np.testing.assert_allclose(w.temp_air[:48], df["temp_air"].to_numpy() + ZERO_CELSIUS - 2.0,
                               atol=1e-9)
    assert w.temp_air[48] == w.temp_air[47]
    assert any("2024-07-16 00:00 +08 lies beyond the record: value of the nearest "
               "observation (2024-07-15 23:00) held" in line for line in sc.check_weather())
    # a date the file does not cover: the record's range and the span needed are named
    late = load_scenario({"weather": {"source": "w.csv"}, "time": {"date": "2024-07-16"}},
                         base_dir=tmp_path)
    with pytest.raises(InputError, match=r"covers 2024-07-14 00:00 … 2024-07-15 23:00 \+08, "
                       r"not the span needed 2024-07-16 00:00"):
        late.environment()


def test_builtin_ship_from_scenario():
    sc = load_scenario({
        "ship": {"builtin": "patrol_boat", "edge_length": 2.0,
                 "layups": {"deck": [{"material": "deck_covering", "thickness": 0.004},
                                     {"material": "mild_steel", "thickness": 0.012, "cells": 2}]},
                 "compartment_temperature": {"superstructure_mast": 280.0, "hull_dry": 290.0}},
        "time": {"season": "winter", "date": "2023-01-20"}})
    ship = sc.ship()
    assert ship.name == "patrol_boat" and ship.length == 56.0
    assert ship.edge_length == 2.0
    assert ship.layups["deck"].thickness == pytest.approx(0.016, abs=1e-15)
    # hull default layup untouched (0.3 mm paint + 14 mm steel)
    assert ship.layups["hull_wetted"].thickness == pytest.approx(0.0143, abs=1e-15)
    ct = ship.compartment_temperature
    assert ct["hull_wetted"] == pytest.approx(295.15) and ct["hull_dry"] == 290.0
    assert ct["superstructure_mast"] == 280.0
    assert ct["superstructure_funnel"] == pytest.approx(295.15)  # takes its main part's
    # per-face values come from the same tables (one value per triangle, by its part)
    eps = sc.face_property(ship, "emissivity", "8-14")
    deck = ship.part_mask("deck")
    assert eps.shape == (ship.n_faces,)
    assert np.all(eps[deck] == 0.95) and np.all(eps[ship.part_mask("hull")] == 0.90)
    temp = sc.face_property(ship, "compartment_temperature")
    np.testing.assert_array_equal(temp, ship.face_compartment_temperature)
    assert np.all(sc.face_property(ship, "solar_absorptivity")[deck] == 0.85)
    with pytest.raises(InputError):
        sc.face_property(ship, "emissivity")
    # every part of the built ship was known at load time (part-name validation is exact)
    from shipthermal.app.scenario.sections import _builtin_part_names
    assert set(ship.part_names) == set(_builtin_part_names("patrol_boat", {}))
    # and the scenario's lookups agree with the built ship for every part
    for part in ship.part_names:
        assert sc.ship.compartment_temperature_of(part) == ct[part]


def test_user_ship_files_round_trip(tmp_path):
    from shipthermal.geometry import patrol_boat, write_ship

    ref = patrol_boat(edge_length=2.0)
    paths = write_ship(ref, tmp_path, stem="pb")
    mesh = next(p for k, p in paths.items() if str(p).endswith(".ply"))
    pmap = next(p for k, p in paths.items() if str(p).endswith(".json"))
    sc = load_scenario({"ship": {"files": {"units": "m", "mesh": mesh.name,
                                           "part_map": pmap.name}}}, base_dir=tmp_path)
    assert sc.ship.builtin is None
    ship, report = sc.ship(return_report=True)
    assert set(ship.part_names) == set(ref.part_names)
    assert ship.n_faces == ref.n_faces
    # read back in metres: the PLY holds float32 vertices, so each coordinate (|x| <= 28 m)
    # moves by <= 28 * 2**-24 = 1.7e-6 m, i.e. <= 1e-6 of a 2 m edge; a triangle's area by
    # <= ~2e-6 relative, and the total by no more (measured 3e-9: the errors average out)
    assert ship.total_area == pytest.approx(ref.total_area, rel=2e-6)
    assert report["units"] == "m"
    assert load_scenario(sc.to_dict()) == sc


def test_emissivities_are_the_papers():
    sc = default_scenario("summer")
    paper = {("hull", "3-5"): 0.85, ("deck", "3-5"): 0.90, ("superstructure", "3-5"): 0.78,
             ("hull", "8-14"): 0.90, ("deck", "8-14"): 0.95, ("superstructure", "8-14"): 0.88}
    for (part, band), eps in paper.items():
        assert sc.emissivity(part, band) == eps
    # sub-parts and the split hull take their main part's value; aliases and sub-bands work
    assert sc.emissivity("hull_wetted", "mwir") == 0.85
    assert sc.emissivity("superstructure_funnel", "lwir") == 0.88
    assert sc.emissivity("deck", "3.7-4.8") == 0.90
    assert sc.emissivity("deck", (10.0, 12.0)) == 0.95
    assert sc.longwave_emissivity("hull_dry") == 0.90
    assert sc.solar_absorptivity("deck") == 0.85
    with pytest.raises(InputError):
        sc.emissivity("mast", "3-5")
    with pytest.raises(InputError, match="no emissivity"):
        sc.emissivity("deck", "5-8")


def test_emissivity_overrides_are_specific():
    sc = load_scenario({"ship": {"band_emissivity": {
        "superstructure_funnel": {"3-5": 0.6}, "hull": {"3.7-4.8": 0.8}}},
        "imaging": {"bands": ["3-5", "3.7-4.8", "8-14"]}})
    assert sc.emissivity("superstructure_funnel", "3-5") == 0.6
    assert sc.emissivity("superstructure_funnel", "8-14") == 0.88   # merged per band
    assert sc.emissivity("superstructure", "3-5") == 0.78
    assert sc.emissivity("hull_dry", "3.7-4.8") == 0.8
    assert sc.emissivity("deck", "3.7-4.8") == 0.90


def test_sensor_is_the_papers():
    from imaging.sensor import PAPER_SENSOR, ground_sample_distance

    sc = default_scenario("winter")
    spec = sc.sensor()
    assert spec == PAPER_SENSOR
    assert float(ground_sample_distance(spec)[0]) == pytest.approx(30.0, abs=1e-9)
    other = load_scenario({"imaging": {"sensor": {"focal_length_m": 2.12}}}).sensor()
    assert dataclasses.replace(other, focal_length_m=1.06) == PAPER_SENSOR


def test_tmy3_file_through_pvlib():
    # pvlib's sample TMY3 (Sand Point, Alaska, UTC-9): the typical year is coerced to the
    # scenario's year, and the periodic day is the file's 20 January, hour for hour
    import os

    import pvlib

    src = os.path.join(os.path.dirname(pvlib.__file__), "data", "703165TY.csv")
    sc = load_scenario({"location": {"latitude": 55.317, "longitude": -160.517,
                                     "time_zone": "Etc/GMT+9"},
                        "time": {"season": "winter", "date": "2023-01-20"},
                        "weather": {"source": src, "format": "tmy3", "temp_sea": 276.0}})
    env = sc.environment()
    assert env.start == pd.Timestamp("2023-01-20", tz="Etc/GMT+9") and env.weather.periodic
    data, _ = pvlib.iotools.read_tmy3(src, coerce_year=2023, map_variables=True)
    day = data.loc["2023-01-20"]
    np.testing.assert_allclose(env.weather.temp_air, day["temp_air"].to_numpy() + ZERO_CELSIUS,
                               atol=1e-9)
    np.testing.assert_array_equal(env.weather.temp_sea, 276.0)
