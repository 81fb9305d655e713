"""One weather for both stages: each frame's atmosphere is the model scaled to the hour."""

import math

import numpy as np
import pytest

from imaging.atmosphere import AtmosphereState, atmosphere, sky_radiance, surface_state
from imaging.atmosphere import weather_sky as ws
from imaging.render import atmosphere_state, conditions_from_atmosphere
from shipthermal.environment import climate_day
from shipthermal.environment.sky import longwave_down

BANDS = ("3-5", "8-14")
ZENITHS = np.array([0.0, 30.0, 60.0, 80.0])


@pytest.mark.parametrize("model", ["summer", "tropical", "subarctic_winter"])
@pytest.mark.parametrize("band", BANDS)
def test_reproduces_the_model_at_its_own_surface_state(model, band):
    s = surface_state(model)
    got = ws.weather_sky_radiance(band, ZENITHS, s.temp_air_K, s.rel_humidity, model=model)
    np.testing.assert_allclose(got, sky_radiance(model, band, ZENITHS), rtol=1e-9)


@pytest.mark.parametrize("cloud_model", ["unsworth_monteith", "crawford_duchon"])
def test_measured_longwave_gives_the_thermal_stages_cloud_share(cloud_model):
    t, rh = 285.0, 60.0
    for c in (0.0, 0.3, 0.8):
        lw = float(longwave_down(t, rh, c, None, "brutsaert", cloud_model))
        assert ws.cloud_share(t, rh, 0.0, lw, "brutsaert", cloud_model) == pytest.approx(
            c, abs=1e-9)
    a = ws.weather_sky_radiance("8-14", 0.0, t, rh, 0.5)
    b = ws.weather_sky_radiance("8-14", 0.0, t, rh, 0.0, longwave_down=float(
        longwave_down(t, rh, 0.5)))
    assert float(b) == pytest.approx(float(a), rel=1e-12)


def test_sky_follows_temperature_humidity_and_cloud():
    base = ws.weather_sky_irradiance("8-14", 290.0, 60.0)
    assert ws.weather_sky_irradiance("8-14", 295.0, 60.0) > base
    assert ws.weather_sky_irradiance("8-14", 290.0, 90.0) > base
    assert ws.weather_sky_irradiance("8-14", 290.0, 60.0, cloud_cover=0.5) > base


def test_state_of_a_moment():
    st, c = atmosphere_state(None, None)
    assert st == AtmosphereState() and c == 0.0
    st, c = atmosphere_state(None, {"wind_speed": 7.0, "wind_speed_24h": 7.0,
                                    "rel_humidity": 80.0})
    assert st.wind_speed == 7.0 and st.rel_humidity == 80.0 and st.temp_air_K is None
    hour = dict(temp_air=288.0, relative_humidity=70.0, cloud_cover=0.4, longwave_down=None,
                clear_model="brutsaert", cloud_model="unsworth_monteith")
    st, c = atmosphere_state(hour, {"wind_speed": 7.0})
    assert (st.temp_air_K, st.rel_humidity, st.wind_speed, c) == (288.0, 70.0, 7.0, 0.4)


def test_sky_weather_from_design_day_and_in_the_render_conditions():
    day = climate_day("summer")
    sw = ws.SkyWeather.from_weather(day.weather())
    assert sw.hours_local[0] == 0.0 and sw.hours_local.size == 24
    at = sw.at(14.5 * 3600.0)
    assert at["temp_air"] == pytest.approx(0.5 * (day.temp_air(14.0) + day.temp_air(15.0)))
    assert sw.at(23.5 * 3600.0)["temp_air"] == pytest.approx(
        0.5 * (day.temp_air(23.0) + day.temp_air(0.0)))   # periodic
    aer = {"wind_speed": 5.0, "wind_speed_24h": 5.0, "rel_humidity": 75.0}
    plain = conditions_from_atmosphere("summer", "8-14", 30.0, 0.0, 50.0, 180.0)
    follow = conditions_from_atmosphere("summer", "8-14", 30.0, 0.0, 50.0, 180.0,
                                        sky_weather=at, aerosol=aer)
    st, c = atmosphere_state(at, aer)
    atm = atmosphere("summer", "8-14", 30.0, 50.0, view_azimuth_from_sun_deg=180.0, state=st,
                     cloud_cover=c)
    assert follow.sky_radiance_specular == pytest.approx(atm.sky_radiance
                                                         + atm.sky_radiance_solar)
    assert follow.sky_radiance_mean == pytest.approx(
        (atm.sky_irradiance + atm.sky_irradiance_solar) / math.pi)
    assert follow.path_radiance == pytest.approx(atm.path_radiance)
    # the hour's state moves the whole atmosphere, not only the sky
    assert follow.path_radiance != plain.path_radiance
    assert follow.sky_radiance_specular != plain.sky_radiance_specular
    # the specular sky's transmittance is the radiance-weighted mean of its two terms
    mix = ((atm.sky_radiance * atm.transmittance_sky_weighted
            + atm.sky_radiance_solar * atm.transmittance_sky_solar_weighted)
           / (atm.sky_radiance + atm.sky_radiance_solar))
    assert follow.transmittance_sky == pytest.approx(mix)
