"""A weather record's images are seen through each day's own model atmosphere.

A year at a mid-latitude port with one model atmosphere (the record's mean) puts January's
overpasses under a summer-like water-vapour column; with the site rule applied day by day
the model follows the season (LOWTRAN surface temperatures: mid-latitude winter 272.2 K,
US 1976 288.2 K, mid-latitude summer 294.2 K; sub-arctic winter 257.2 K is the coldest).
"""

import warnings

import numpy as np
import pytest

from imaging.atmosphere import model_for_record_day, model_for_site
from imaging.atmosphere.models import MAX_TEMP_OFFSET_K
from imaging.atmosphere.weather_sky import SkyWeather
from imaging.experiment import ImagingScenario
from shipthermal.units import DAY


def _year_sky(temp_of_day):
    days = np.arange(365)
    hours = np.arange(0.0, 365 * 24.0, 1.0)
    temp = np.repeat([temp_of_day(d) for d in days], 24) + 3.0 * np.sin(
        2 * np.pi * (hours % 24 - 9.0) / 24.0)       # a diurnal cycle with zero mean
    n = hours.size
    return SkyWeather(hours_local=hours, temp_air=temp, relative_humidity=np.full(n, 70.0),
                      cloud_cover=np.zeros(n), periodic=False)


def _scenario(sky, by_day=True, model="us_standard_1976"):
    return ImagingScenario(season=model, background=None, date="2021-01-01", latitude=42.4,
                           longitude=-70.6, tz="Etc/GMT+5", wind_speed=5.0, sky_weather=sky,
                           atmosphere_model=model, atmosphere_by_day=by_day)


def test_each_day_of_a_record_gets_the_model_of_its_own_mean_and_month():
    # a seasonal cycle 270 K (mid-January) to 296 K (mid-July)
    sky = _year_sky(lambda d: 283.0 - 13.0 * np.cos(2 * np.pi * (d - 14) / 365.0))
    sc = _scenario(sky)
    jan, apr, jul = 14, 105, 195
    assert sc.atmosphere_model_at(jan * DAY + 10 * 3600.0) == "midlatitude_winter"
    assert sc.atmosphere_model_at(jul * DAY + 10 * 3600.0) == "midlatitude_summer"
    # the rule is model_for_site on the day's mean (the diurnal cycle averages out)
    mean_apr = 283.0 - 13.0 * np.cos(2 * np.pi * (apr - 14) / 365.0)
    assert sc.atmosphere_model_at(apr * DAY + 1.0) == model_for_site(42.4, 4, mean_apr)
    # every hour of one local day shares its model; the next day may differ
    models = {sc.atmosphere_model_at(jul * DAY + h * 3600.0) for h in range(24)}
    assert models == {"midlatitude_summer"}
    # without by-day placement, or with a periodic day, the one model throughout
    fixed = _scenario(sky, by_day=False)
    assert {fixed.atmosphere_model_at(d * DAY) for d in (jan, jul)} == {"us_standard_1976"}
    periodic = SkyWeather(hours_local=np.arange(24.0), temp_air=np.full(24, 296.0),
                          relative_humidity=np.full(24, 70.0), cloud_cover=np.zeros(24))
    assert _scenario(periodic).atmosphere_model_at(jul * DAY) == "us_standard_1976"


def test_an_extreme_day_gets_the_nearest_model_and_a_warning():
    cold = 257.2 - MAX_TEMP_OFFSET_K - 5.0         # beyond sub-arctic winter's reach
    assert model_for_record_day(65.0, 1, cold) == ("subarctic_winter", True)
    assert model_for_record_day(42.4, 7, 294.0) == ("midlatitude_summer", False)
    with pytest.raises(Exception, match="must lie within"):
        model_for_site(65.0, 1, cold)                # the single-day rule still refuses
    sc = _scenario(_year_sky(lambda d: cold if d == 3 else 275.0))
    with pytest.warns(UserWarning, match="2021-01-04.*subarctic_winter"):
        assert sc.atmosphere_model_at(3 * DAY + 5.0) == "subarctic_winter"
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert sc.atmosphere_model_at(2 * DAY) == "midlatitude_winter"
