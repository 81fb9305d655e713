"""Tests for the thermal-history hand-over, the time series and the paper's experiment."""

import os

import numpy as np
import pandas as pd
import pytest
import rasterio
import xarray as xr

from imaging.experiment import (PAPER_TYPICAL_HOURS, ImagingScenario, render_series,
                                run_experiment)
from imaging.scene import GriddedBackground, ShipPlacement
from imaging.thermal_history import ShipThermalHistory, synthetic_history
from shipthermal.errors import InputError
from shipthermal.raytrace.scenes import box
from shipthermal.units import strip_units

DALIAN = dict(date="2023-07-15", latitude=38.91, longitude=121.63, tz="Etc/GMT-8")


@pytest.fixture(scope="module")
def frigate_coarse():
    from shipthermal.geometry import frigate

    return frigate(edge_length=2.0)


def _box_history(times, temps):
    V, F = box([-10.0, -3.0, -1.0], [10.0, 3.0, 4.0])
    temps = np.asarray(temps, dtype=float)
    return ShipThermalHistory(V, F, np.zeros(len(F), int), ("deck",), times,
                              np.repeat(temps[:, None], len(F), axis=1))


def test_history_interpolates_linearly_and_wraps_over_the_day():
    h = _box_history([0.0, 3600.0, 7200.0], [280.0, 290.0, 286.0])
    assert h.at(1800.0) == pytest.approx(np.full(h.n_faces, 285.0), abs=1e-12)
    assert h.at(5400.0)[0] == pytest.approx(288.0, abs=1e-12)
    # periodic (default one day): between the last sample (2 h) and the first one a day later
    assert h.at(7200.0 + 0.5 * (86400.0 - 7200.0))[0] == pytest.approx(283.0, abs=1e-12)
    assert h.at(86400.0 + 1800.0)[0] == pytest.approx(285.0, abs=1e-12)
    assert h.at(-1800.0)[0] == pytest.approx(h.at(86400.0 - 1800.0)[0], abs=1e-12)
    strict = ShipThermalHistory(h.vertices, h.faces, h.face_part, h.part_names, h.times_s,
                                h.face_temperature, period_s=None)
    with pytest.raises(InputError, match="t"):
        strict.at(7300.0)


def test_history_validation_names_the_field():
    V, F = box([0, 0, 0], [1, 1, 1])
    with pytest.raises(InputError, match="face_temperature"):
        ShipThermalHistory(V, F, np.zeros(len(F), int), ("deck",), [0.0, 1.0],
                           np.full((2, len(F) + 1), 290.0))
    with pytest.raises(InputError, match="times_s"):
        ShipThermalHistory(V, F, np.zeros(len(F), int), ("deck",), [1.0, 0.0],
                           np.full((2, len(F)), 290.0))
    with pytest.raises(InputError, match="face_temperature"):
        ShipThermalHistory(V, F, np.zeros(len(F), int), ("deck",), [0.0, 1.0],
                           np.full((2, len(F)), 29.0))          # degC by mistake
    with pytest.raises(InputError, match="part name"):
        ShipThermalHistory(V, F, np.zeros(len(F), int), ("bridge",), [0.0, 1.0],
                           np.full((2, len(F)), 290.0))


def test_synthetic_history_is_labelled_and_follows_the_air_temperature(frigate_coarse):
    from shipthermal.environment import climate_day

    h = synthetic_history(frigate_coarse, "winter")
    assert h.label.startswith("SYNTHETIC")
    day = climate_day("winter")
    assert h.temp_air_at(5 * 3600.0) == pytest.approx(float(day.temp_air(5.0)), abs=1e-9)
    deck = h.part_mean(13 * 3600.0)["deck"]
    assert deck > h.temp_air_at(13 * 3600.0) + 2.0          # sunlit deck warmer than the air
    assert h.part_mean(2 * 3600.0)["deck"] < h.temp_air_at(2 * 3600.0)   # night: colder


def test_series_finds_a_known_crossover_at_ten_minute_resolution(frigate_coarse):
    # black ship on black water at night: contrast = tau B(T_ship) - tau B(T_water) (no
    # reflections), zero exactly when the temperatures cross; ship warms 2 K/h through
    # T_water = 290 K at 21:37:00 local (summer sunset at Dalian is ~19:30)
    t_cross = 21 * 3600.0 + 37 * 60.0
    times = np.array([0.0, 86400.0])
    temps = 290.0 + 2.0 * (times - t_cross) / 3600.0
    h = ShipThermalHistory(frigate_coarse.vertices, frigate_coarse.faces,
                           frigate_coarse.face_part, frigate_coarse.part_names, times,
                           np.repeat(temps[:, None], frigate_coarse.n_faces, axis=1))
    one = {"hull": 1.0, "deck": 1.0, "superstructure": 1.0}
    scen = ImagingScenario(
        "summer", GriddedBackground.uniform((20, 20), 1, 290.0), wind_speed=4.0,
        placement=ShipPlacement(300.0, 300.0, 30.0), samples_per_pixel=16,
        renderer_options=dict(ship_emissivity={"8-14": one},
                              background_emissivity={"8-14": {"water": 1.0}}), **DALIAN)
    frame_times = np.arange(20 * 3600.0, 86400.0 + 1.0, 600.0)
    res = render_series(h, scen, ("8-14",), frame_times, progress=False)["8-14"]
    assert res.metrics["sun_zenith_deg"].min() > 90.0        # really night
    assert len(res.crossovers) == 1 and res.crossovers[0].direction == "dark->bright"
    # requirement: within one minute; measured error ~0.1 s (contrast is smooth in T)
    assert abs(res.crossovers[0].time - t_cross) < 60.0
    assert res.metrics["contrast"].iloc[0] < 0 < res.metrics["contrast"].iloc[-1]


def _textured_port(shape=(40, 40)):
    """Water with a +-0.3 K checkerboard (finite SCR) and a diurnal cycle; a land strip."""
    cm = np.ones(shape, np.uint8)
    cm[:, :4] = 3
    hours = np.arange(24.0)
    yy, xx = np.mgrid[0:shape[0], 0:shape[1]]
    tex = 0.3 * np.where((yy + xx) % 2 == 0, 1.0, -1.0)
    base = 292.0 + 1.0 * np.cos(2 * np.pi * (hours - 15.0) / 24.0)
    temp = base[:, None, None] + tex[None] + np.where(cm == 3, 4.0, 0.0)[None]
    return GriddedBackground(cm, hours, temp, 30.0)


def test_run_experiment_writes_every_product_atomically(tmp_path, frigate_coarse):
    hist = {s: synthetic_history(frigate_coarse, s) for s in ("summer", "winter")}
    scen = {s: ImagingScenario.default(s, background=_textured_port(),
                                       placement=ShipPlacement(700.0, 600.0, 0.0))
            for s in hist}
    times = np.arange(0.0, 86400.0 + 1.0, 2 * 3600.0)
    res = run_experiment(hist, tmp_path, times=times, progress=False, scenarios=scen,
                         crop_px=24)
    n_typ = {s: len(PAPER_TYPICAL_HOURS[s]) for s in hist}
    for (season, band), sr in res.series.items():
        # the paper's typical times were added to the 2-hourly frames
        assert len(sr.times_s) == len(np.union1d(times, np.array(PAPER_TYPICAL_HOURS[season])
                                                 * 3600.0))
        ds = xr.open_dataset(tmp_path / f"images_{season}_{band}.nc", engine="h5netcdf")
        assert ds["radiance"].dtype == np.float32 and ds["radiance"].attrs["units"] == "W m-2 sr-1"
        assert ds["radiance"].shape == (len(sr.times_s), 24, 24)
        np.testing.assert_allclose(ds["time_local_h"].values, sr.times_s / 3600.0)
        # CF time: local midnight of the scenario's date at UTC+8 is 16:00 UTC the day before
        assert scen[season].tz == "Etc/GMT-8"
        midnight_utc = np.datetime64(f"{scen[season].date}T00:00") - np.timedelta64(8, "h")
        np.testing.assert_array_equal(ds["time"].values, midnight_utc + (
            sr.times_s * 1e9).round().astype("timedelta64[ns]"))
        assert float(ds["coverage"].sum()) == pytest.approx(float(sr.coverage.sum()))
        ds.close()
        with rasterio.open(tmp_path / f"typical_{season}_{band}.tif") as tif:
            assert tif.count == n_typ[season] and tif.dtypes[0] == "float32"
            k = sorted(sr.frames)[0]
            np.testing.assert_array_equal(tif.read(1), sr.frames[k].radiance)
        df = strip_units(pd.read_csv(tmp_path / f"metrics_{season}_{band}.csv"))
        assert len(df) == len(sr.times_s) and np.isfinite(df["scr"]).all()
        assert df.attrs["units"]["contrast"] == "W m-2 sr-1"
    for band in ("3-5", "8-14"):
        assert os.path.getsize(tmp_path / f"panels_{band}.png") > 10_000
        assert os.path.getsize(tmp_path / f"scr_{band}.png") > 10_000
    cross = pd.read_csv(tmp_path / "crossovers.csv")
    assert list(cross.columns) == ["season", "band", "time_h [h]", "date_local [UTC+8]",
                                   "time_local [UTC+8]", "direction"]
    comp = strip_units(pd.read_csv(tmp_path / "band_comparison.csv"))
    assert len(comp) == 4 and {"scr_in_crossover_mean", "scr_out_crossover_mean"} <= set(comp)
    assert (tmp_path / "summary.json").exists()
    assert not [q for q in tmp_path.iterdir() if ".part" in q.name or ".tmp" in q.name]


@pytest.mark.parametrize("x_m, options", [(600.0, None), (70.0, "bits")])
def test_frames_not_kept_render_only_the_scr_window_with_the_same_metrics(frigate_coarse,
                                                                          x_m, options):
    # a series keeping every frame renders each whole; keeping none, it renders only the
    # local SCR's window of each frame (SceneRenderer.window_radiance): the metrics must be
    # the same to the bit, by day (sun, shadows on a textured port with land) and by night,
    # with the ship mid-port and at the image's edge (window clipped), with quantisation
    from imaging.render import SensorOptions

    h = synthetic_history(frigate_coarse, "summer", 3 * 3600.0)
    opts = SensorOptions(bits=12, radiance_range=(0.0, 20.0)) if options == "bits" else None
    scen = ImagingScenario("summer", _textured_port((40, 40)), wind_speed=4.0,
                           placement=ShipPlacement(x_m, 600.0, 30.0), samples_per_pixel=4,
                           sensor_options=opts, **DALIAN)
    frames = np.arange(3 * 3600.0, 24 * 3600.0, 2 * 3600.0)
    every = render_series(h, scen, ("8-14",), frames, progress=False)["8-14"]
    window = render_series(h, scen, ("8-14",), frames, progress=False,
                           stack_step_s=1e12)["8-14"]
    assert window.radiance.shape[0] == 1 and every.radiance.shape[0] == len(frames)
    assert (window.metrics["sun_zenith_deg"] < 90).any() and \
        (window.metrics["sun_zenith_deg"] > 90).any()
    pd.testing.assert_frame_equal(window.metrics, every.metrics, check_exact=True)
    if x_m < 100.0:     # the ship at the edge: the window is clipped to the image
        assert every.metrics["n_background"].iloc[0] > 0


def test_window_radiance_refuses_options_that_mix_pixels(frigate_coarse):
    from imaging.render import SensorOptions

    h = synthetic_history(frigate_coarse, "summer", 3 * 3600.0)
    scen = ImagingScenario("summer", _textured_port((40, 40)), wind_speed=4.0,
                           placement=ShipPlacement(600.0, 600.0, 30.0), samples_per_pixel=4,
                           **DALIAN)
    r = scen.renderer(h)
    with pytest.raises(InputError, match="sensor_options"):
        r.window_radiance(None, h.at(0.0), scen.background.temperature_at(0.0), (0, 5, 0, 5),
                          sensor_options=SensorOptions(psf=True))
