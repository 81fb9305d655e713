"""The physical background end to end: one world with the ship (the same weather, sun and sea
at any site), anchoring on a scene, weather records, orientation grouping, bad input."""

from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import imaging.background.physical.columns as P_columns
import imaging.background.physical.result as P_result
from imaging.background.landsat import SceneGrid
from imaging.background.physical import (GroundCover, Observation, build_physical_background,
                                         ground_from_synthetic)
from shipthermal.app.scenario import default_scenario, load_scenario
from shipthermal.errors import InputError

DATA = Path(__file__).resolve().parents[1] / "data" / "weather"
SOTON = DATA / "southampton_2023-07-15.csv"
NDBC = DATA / "44009h2013_mar03-09.txt"


def _soton(tmp_path, extra=""):
    f = tmp_path / "s.toml"
    f.write_text(f"""
[location]
latitude = 50.90
longitude = -1.40
time_zone = "Europe/London"
[time]
date = 2023-07-15
[weather]
source = "{SOTON}"
[background]
size_px = 100
{extra}""")
    return load_scenario(f)


@pytest.fixture(scope="module")
def soton(tmp_path_factory):
    sc = _soton(tmp_path_factory.mktemp("soton"))
    env = sc.environment()
    ground = ground_from_synthetic(50.90, -1.40, size_px=100, seed=2026)
    return sc, env, ground, build_physical_background(ground, env)


def test_water_is_the_ships_sea_at_every_hour(soton):
    # The user's file says 15.5 C (288.65 K); the water pixels are that sea (its skin where
    # the skin model is on) plus the synthetic port's fixed pattern (0.24 K, zero mean over
    # the generated field): the median water pixel stays within 1 K of the file's sea at every
    # hour, and equals the sea the ship's environment gives to round-off.
    sc, env, _, bg = soton
    water = bg.class_map == 1
    hours = np.arange(0.0, 24.0, 0.5)
    st = env.at(hours * 3600.0)
    sea = np.asarray(getattr(st, "temp_sea_skin", st.temp_sea))
    for h, ts in zip(hours, sea):
        layer = bg.temperature_at(h)
        assert abs(np.median(layer[water]) - 288.65) < 1.0
        assert bg.sea_temperature_at(h) == pytest.approx(ts, abs=1e-9)
        np.testing.assert_allclose(layer[water], ts + bg.water_anomaly, atol=1e-4)


def test_synthetic_port_follows_the_site_and_says_so(soton):
    # Nothing of Dalian's climate: the Southampton port's land sits near Southampton's air at
    # night, the Dalian design day's near Dalian's (air 294.6 K at midnight, the file's
    # 15.4 C = 288.55 K); the label says synthetic everywhere.
    sc, env, ground, bg = soton
    assert bg.synthetic and "synthetic port" in bg.label and "50.90 N 1.40 W" in bg.label
    dal = default_scenario("summer")
    bd = build_physical_background(ground_from_synthetic(38.93, 121.65, size_px=100),
                                   dal.environment())
    land = bg.class_map == 2                     # vegetation: close to the air at night
    t_soton = np.median(bg.temperature_at(0.0)[land])
    t_dal = np.median(bd.temperature_at(0.0)[bd.class_map == 2])
    assert abs(t_soton - 288.55) < 3.0 and abs(t_dal - 294.58) < 3.0
    assert bd.start.tz.zone if hasattr(bd.start.tz, "zone") else True
    assert bg.utc_offset_hours == 1.0 and bd.utc_offset_hours == 8.0
    s = bg.summary()
    assert s["synthetic"] and "synthetic port" in s["background"]


def test_periodic_day_wraps_and_record_does_not(soton):
    _, env, ground, bg = soton
    np.testing.assert_allclose(bg.temperature_at(24.0), bg.temperature_at(0.0), atol=1e-5)
    np.testing.assert_allclose(bg.temperature_at(30.5), bg.temperature_at(6.5), atol=1e-5)


def test_frame_kernel_equals_reference(soton):
    bg = soton[3]
    col = bg.column_temperature[100].astype(float)
    a = np.zeros(bg.class_map.size, np.float32)
    b = np.zeros(bg.class_map.size, np.float32)
    P_result._land_frame(col, bg.corners, bg.weights, bg.residual, 0.7, bg.land, a)
    P_result._land_frame_reference(col, bg.corners, bg.weights, bg.residual, 0.7, bg.land, b)
    np.testing.assert_allclose(a[bg.land], b[bg.land], rtol=0, atol=2e-5)   # float32 sums


def test_anchoring_reproduces_its_own_scene_exactly(soton):
    # A scene made by the model itself (its own temperatures at 11:00 UTC) is explained by
    # the fit with no residual, and the anchored day equals the free day: the inversion
    # recovers each pixel's albedo / wetness on the columns it interpolates.
    sc, env, ground, bg = soton
    when = pd.Timestamp("2023-07-15 11:00", tz="UTC")
    hour = (when.tz_convert("Europe/London") - bg.start).total_seconds() / 3600.0
    obs = Observation(bg.temperature_at(hour), when, "model's own scene", 0.0)
    anchored = build_physical_background(
        GroundCover(**{**ground.__dict__, "observation": obs, "origin": "scene"}), env)
    # the scene and the column tables are float32: 3.05e-5 K apart at 300 K
    assert max(abs(f.residual_median_K) for f in anchored.fits) < 3.1e-5
    assert max(f.residual_rms_K for f in anchored.fits) < 1e-3
    land = anchored.class_map != 1
    for h in (3.0, 9.0, 12.0, 15.0, 21.0):
        np.testing.assert_allclose(anchored.temperature_at(h)[land], bg.temperature_at(h)[land],
                                   atol=2e-3)


def test_anchoring_reports_what_it_cannot_reach(soton):
    # A scene 8 K hotter than the darkest, driest surface the classes allow: the fit stops at
    # the bound, the residual is the rest (reported per class; at the overpass T = LST).
    sc, env, ground, bg = soton
    when = pd.Timestamp("2023-07-15 11:00", tz="UTC")
    hour = (when.tz_convert("Europe/London") - bg.start).total_seconds() / 3600.0
    hot = bg.temperature_at(hour) + 40.0
    obs = Observation(hot, when, "a hot scene", 1.5)
    anchored = build_physical_background(
        GroundCover(**{**ground.__dict__, "observation": obs, "origin": "scene"}), env)
    for f in anchored.fits:
        assert f.at_bound_fraction > 0.99 and f.residual_median_K > 10.0
    assert any("WARNING" in n and "warmer" in n for n in anchored.notes)
    land = anchored.class_map != 1
    np.testing.assert_allclose(anchored.temperature_at(hour)[land], hot[land], atol=2e-3)


def test_orientation_groups_against_every_pixel_its_own_column(soton, monkeypatch):
    # Sloped pixels of one class solved in their orientation groups (SLOPE_EDGES_DEG x 24
    # sectors of 15 deg) against each pixel solved at its own slope and aspect. Within a
    # group the direct beam's cos(incidence) differs by up to sin(s) cos(e) sin(7.5 deg)
    # (aspect) plus the slope spread: for s = 40 deg, sun elevation e = 62 deg at noon, about
    # 0.04 + 0.05 of ~870 W m-2 DNI, i.e. ~80 W m-2 on the worst pixel; with ~25 W m-2 K-1 of
    # combined exchange on dark paving that is ~3 K at the instant, ~1.5 K after the
    # pavement's storage smooths it. Measured: 1.31 K max, 0.11 K mean.
    sc, env, ground, _ = soton
    rng = np.random.default_rng(5)
    n = 20
    slope = rng.uniform(0.0, 40.0, (n, n)).astype(np.float32)
    aspect = rng.uniform(0.0, 360.0, (n, n)).astype(np.float32)
    grid = SceneGrid(ground.grid.transform, ground.grid.crs, (n, n))
    g = GroundCover(grid, np.full((n, n), 3, np.uint8), np.zeros((n, n), np.float32), slope,
                    aspect, np.full((n, n), 0.12, np.float32), "test", "user", "test slopes")
    grouped = build_physical_background(g, env)

    def own(slope_deg, aspect_deg):
        s = np.asarray(slope_deg, float)
        return (np.arange(s.size).reshape(s.shape), s.ravel().copy(),
                np.asarray(aspect_deg, float).ravel().copy())

    monkeypatch.setattr(P_columns, "orientation_bins", own)
    exact = build_physical_background(g, env)
    diff = np.array([grouped.temperature_at(h) - exact.temperature_at(h)
                     for h in np.arange(0.0, 24.0, 1.0)])
    assert np.abs(diff).max() < 1.5, np.abs(diff).max()
    assert np.abs(diff).mean() < 0.15, np.abs(diff).mean()


def test_weather_record_drives_the_background(tmp_path):
    # Three days of NOAA buoy 44009: the background follows the record (not a repeated day),
    # the water is the buoy's own sea temperature hour by hour, and times outside the
    # record are refused.
    import shutil

    shutil.copy(NDBC, tmp_path / "buoy.txt")
    (tmp_path / "b.toml").write_text("""
[location]
latitude = 38.46
longitude = -74.70
time_zone = "Etc/GMT+5"
[time]
date = 2013-03-04
[weather]
source = "buoy.txt"
day = "record"
days = 3
wind_height = 5.0
cloud_cover = 0.5
[background]
size_px = 80
""")
    sc = load_scenario(tmp_path / "b.toml")
    env = sc.environment()
    from shipthermal.app.pipeline import record_span_s

    end = record_span_s(sc)
    assert end == 3 * 86400.0
    bg = build_physical_background(ground_from_synthetic(38.46, -74.70, size_px=80), env,
                                   end_s=end)
    assert bg.period_s is None and bg.times_s[-1] == end
    hours = np.arange(0.0, 72.0, 3.0)
    st = env.at(hours * 3600.0)
    sea = np.asarray(getattr(st, "temp_sea_skin", st.temp_sea))
    got = np.array([bg.sea_temperature_at(h) for h in hours])
    np.testing.assert_allclose(got, sea, atol=1e-9)
    land = bg.class_map == 3
    day1 = np.median(bg.temperature_at(12.0)[land])
    day3 = np.median(bg.temperature_at(60.0)[land])
    assert abs(day1 - day3) > 0.05                     # not the same day repeated
    with pytest.raises(InputError, match="simulated span"):
        bg.temperature_at(80.0)


def test_real_scene_whole_day_without_a_met_grid():
    # The Mersey example: a real Landsat-8 Level-2 scene + a weather file, no met grid: the
    # whole day comes out, anchored on the scene (T = LST at the overpass for every land
    # pixel, 'solar' residual), the fit reported per class, the water the weather's sea with
    # the scene's pattern, and the scene named in every label.
    from shipthermal.app.pipeline import build_background

    root = Path(__file__).resolve().parents[2] / "examples" / "real_port"
    sc = load_scenario(root / "ship_in_port.toml")
    bg = build_background(sc)
    assert not bg.synthetic and "Landsat" in bg.label and "ST_B10" in bg.label
    assert {f.name for f in bg.fits} == {"vegetation", "land", "building"}
    for f in bg.fits:
        assert f.pixels > 1000 and np.isfinite(f.residual_rms_K)
    obs = bg.ground.observation
    hour = (obs.time_utc.tz_convert(sc.location.time_zone) - bg.start).total_seconds() / 3600
    at = bg.temperature_at(hour)
    land = bg.class_map != 1
    np.testing.assert_allclose(at[land], obs.lst[land], atol=1e-3)
    water = ~land
    assert abs(np.median(at[water]) - bg.sea_temperature_at(hour)) < 1e-3
    day = np.stack([bg.temperature_at(h) for h in range(24)])
    assert np.isfinite(day).all() and 260.0 < day.min() and day.max() < 330.0
    s = bg.summary()
    assert s["anchored_on"].startswith("Landsat") and not s["synthetic"]
    assert any("scene water median" in n for n in bg.notes)


def test_bad_background_input_exit_2_and_nothing_written(tmp_path, capsys):
    # a class property out of its range, an unknown class, and a scene three months from the
    # date (with a weather file of that date): exit 2 with the key and the fix, no run folder
    from shipthermal.app.cli import main

    root = Path(__file__).resolve().parents[2] / "examples" / "real_port"
    base = (root / "ship_in_port.toml").read_text().replace(
        'source = "liverpool', f'source = "{root.as_posix()}/liverpool').replace(
        '"data/', f'"{root.as_posix()}/data/')
    cases = {
        "albedo": (base + "\n[background.classes.land]\nalbedo = 1.5\n",
                   "background.classes.land.albedo = 1.5: must lie in [0, 1]"),
        "unknown": (base + "\n[background.classes.gravel]\nalbedo = 0.2\n",
                    "background.classes.gravel"),
        "far": (base.replace("date = 2020-09-27", "date = 2020-12-27").replace(
                    f"{root.as_posix()}/liverpool_design_day_2020-09-27.csv",
                    (tmp_path / "december.csv").as_posix()),
                "days away"),
    }
    (tmp_path / "december.csv").write_text(
        (root / "liverpool_design_day_2020-09-27.csv").read_text().replace("2020-09-27",
                                                                            "2020-12-27"))
    for name, (text, expect) in cases.items():
        f = tmp_path / f"{name}.toml"
        f.write_text(text)
        out = tmp_path / f"out-{name}"
        code = main(["-q", "run", str(f), "--image", "--out", str(out)])
        err = capsys.readouterr().err
        assert code == 2 and expect in err, err
        assert err.startswith("error: ") and "Traceback" not in err
        assert not out.exists()
