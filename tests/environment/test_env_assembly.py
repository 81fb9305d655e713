"""Environment assembly: sun vector, irradiance, sky, sea and wind together."""

import numpy as np
import pandas as pd
import pytest

from shipthermal.environment import (Environment, Weather, climate_day, sky, sun,
                                     to_ship_frame)
from shipthermal.errors import InputError
from shipthermal.units import SIGMA

T_DAY = np.arange(0, 86400, 600.0)


@pytest.fixture(scope="module")
def summer():
    return Environment.from_climate_day(climate_day("summer"), ship_heading=90.0, ship_speed=5.0)


def test_state_shapes_units_and_closure(summer):
    st = summer.at(T_DAY)
    n = len(T_DAY)
    assert st.sun_vector.shape == (n, 3)
    np.testing.assert_allclose(np.linalg.norm(st.sun_vector, axis=1), 1, atol=1e-12)
    night = st.zenith >= 90
    assert night.any() and (~night).any()
    assert np.all(st.dni[night] == 0) and np.all(st.dhi[night] == 0)
    cosz = np.clip(st.sun_vector[:, 2], 0, None)
    np.testing.assert_allclose(st.ghi, st.dni * cosz + st.dhi, atol=1e-9)
    # sun vector z is cos(zenith); the sun rises in the east half, sets in the west half
    np.testing.assert_allclose(st.sun_vector[:, 2], np.cos(np.radians(st.zenith)), atol=1e-12)
    rise = np.flatnonzero(~night)[0]
    assert st.sun_vector[rise, 0] > 0 and st.sun_vector[np.flatnonzero(~night)[-1], 0] < 0
    assert np.all((st.temp_air > 290) & (st.temp_air < 300))
    np.testing.assert_allclose(st.temp_sky, (st.longwave_down / SIGMA) ** 0.25)
    assert np.all(st.temp_sky < st.temp_air)      # clear-ish sky is colder than the air
    assert np.all(st.sea_longwave_up > st.longwave_down)  # sea warmer than sky
    df = st.to_frame()
    assert {"sun_x", "sun_y", "sun_z", "dni", "temp_sea"} <= set(df.columns)


def test_periodic_days_repeat_exactly(summer):
    a = summer.at(T_DAY)
    b = summer.at(T_DAY + 4 * 86400)
    for name in ("dni", "dhi", "temp_air", "longwave_down", "temp_sea"):
        np.testing.assert_allclose(getattr(a, name), getattr(b, name), rtol=1e-12)
    np.testing.assert_allclose(a.sun_vector, b.sun_vector, atol=1e-12)


def test_state_carries_true_wind_and_ship_motion(summer):
    # the state holds the design day's true wind at 10 m (south, 4 m/s) and the ship's
    # motion; the apparent wind is the forcing's (at face height, tests/forcing)
    st = summer.at([43200.0])
    day = climate_day("summer")
    assert st.wind_speed[0] == pytest.approx(day.wind_speed, rel=1e-12)
    assert st.wind_direction[0] == pytest.approx(day.wind_direction, abs=1e-9)
    assert (st.ship_speed, st.ship_heading) == (5.0, 90.0)


def test_datetime_and_seconds_agree(summer):
    times = summer.start + pd.to_timedelta([3600.0 * 9, 3600.0 * 15], unit="s")
    a, b = summer.at(times), summer.at([3600.0 * 9, 3600.0 * 15])
    np.testing.assert_allclose(a.dni, b.dni)
    with pytest.raises(InputError, match="time-zone aware"):
        summer.at(pd.DatetimeIndex(["2023-07-15 12:00"]))


def test_winter_sun_lower_than_summer():
    s = Environment.from_climate_day(climate_day("summer")).at([12 * 3600.0])
    w = Environment.from_climate_day(climate_day("winter")).at([12 * 3600.0])
    # near noon: elevation ~ 90 - 38.9 + decl -> ~72 deg in July, ~30 deg in January
    assert s.zenith[0] < 20 and 58 < w.zenith[0] < 62
    assert s.ghi[0] > w.ghi[0] > 0


def test_measured_ghi_and_longwave_paths():
    t = pd.date_range("2024-07-15", periods=24, freq="h", tz="Etc/GMT-8")
    pos = sun.solar_position(t, 38.91, 121.63)
    cs = sun.clearsky_irradiance(t, 38.91, 121.63, 0.0, pos["apparent_zenith"])
    lw = np.full(24, 400.0)
    w = Weather(t, 295.0, 80.0, 3.0, 180.0, 0.3, 296.0, ghi=0.8 * cs["ghi"].to_numpy(),
                longwave_down=lw)
    env = Environment(38.91, 121.63, w)
    st = env.at(np.arange(0, 23 * 3600 + 1, 3600.0))
    np.testing.assert_allclose(st.longwave_down, 400.0)     # measured value used
    np.testing.assert_allclose(st.ghi, 0.8 * cs["ghi"].to_numpy(), atol=1e-6)  # measured GHI kept
    # without the measured long-wave the model is used
    w2 = Weather(t, 295.0, 80.0, 3.0, 180.0, 0.3, 296.0)
    st2 = Environment(38.91, 121.63, w2, clear_sky_model="prata",
                      cloud_model="crawford_duchon").at([0.0])
    expected = sky.longwave_down(295.0, 80.0, 0.3, clear_model="prata",
                                 cloud_model="crawford_duchon")
    assert st2.longwave_down[0] == pytest.approx(float(expected))
    with pytest.raises(InputError, match="within the weather record"):
        env.at([30 * 3600.0])


@pytest.mark.parametrize("kwargs, match", [
    (dict(ship_speed=-1.0), "ship_speed"),
    (dict(latitude=80.0), "latitude"),
    (dict(clear_sky_model="idso"), "clear_sky_model"),
    (dict(date="2023-08-01", periodic=False), "periodic"),
])
def test_bad_environment_inputs(kwargs, match):
    t = pd.date_range("2024-07-15", periods=24, freq="h", tz="Etc/GMT-8")
    w = Weather(t, 295.0, 80.0, 3.0, 180.0, 0.3, 296.0, periodic=kwargs.pop("periodic", True))
    args = dict(latitude=38.91, longitude=121.63, weather=w)
    args.update(kwargs)
    with pytest.raises(InputError, match=match):
        Environment(**args)


def test_date_override_moves_the_sun():
    day = climate_day("summer")
    a = Environment.from_climate_day(day).at([12 * 3600.0])
    b = Environment.from_climate_day(day, date="2023-12-21").at([12 * 3600.0])
    assert b.zenith[0] > a.zenith[0] + 40      # December sun much lower
    assert b.temp_air[0] == pytest.approx(a.temp_air[0])  # same weather day


def test_ship_frame_rotation():
    # heading east: the eastern sun is dead ahead, a northern one on the port beam
    v = to_ship_frame([[1.0, 0, 0], [0, 1.0, 0], [0, 0, 1.0]], 90.0)
    np.testing.assert_allclose(v, [[1, 0, 0], [0, 1, 0], [0, 0, 1]], atol=1e-12)
    rng = np.random.default_rng(3)
    w = rng.normal(size=(50, 3))
    r = to_ship_frame(w, 123.0)
    np.testing.assert_allclose(np.linalg.norm(r, axis=1), np.linalg.norm(w, axis=1))
    # right-handed: determinant of the rotation +1
    m = to_ship_frame(np.eye(3), 123.0)
    assert np.linalg.det(m) == pytest.approx(1.0)


def test_perturbed_climate_day_for_sensitivity():
    day = climate_day("summer")
    p = day.perturbed(wind=1.0, air=1.0, cloud=0.2)
    h = np.arange(0, 24, 0.5)
    np.testing.assert_allclose(p.temp_air(h), day.temp_air(h) + 1.0)
    assert p.wind_speed == day.wind_speed + 1.0
    assert p.cloud_cover == pytest.approx(day.cloud_cover + 0.2)
    assert day.perturbed(wind=-10.0).wind_speed == 0.0
    assert day.perturbed(cloud=-1.0).cloud_cover == 0.0
    e0 = Environment.from_climate_day(day).at([12 * 3600.0])
    e1 = Environment.from_climate_day(day.perturbed(cloud=0.2)).at([12 * 3600.0])
    assert e1.ghi[0] < e0.ghi[0] and e1.longwave_down[0] > e0.longwave_down[0]
