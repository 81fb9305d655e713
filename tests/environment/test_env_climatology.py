"""Built-in Dalian design days reproduce their stated sources."""

import numpy as np
import pytest

from shipthermal.environment import climatology as cl
from shipthermal.environment import sun
from shipthermal.errors import InputError

C0 = 273.15
DAYS = [cl.dalian_summer(), cl.dalian_winter()]
# the sourced values as printed in the module docstring ([A], [B], [C])
STATED = {"dalian_summer": dict(tmax=26.0, tmin=20.7, tmean=23.0, rh=84.0, sun=7.4),
          "dalian_winter": dict(tmax=-1.2, tmin=-8.2, tmean=-4.9, rh=55.0, sun=6.8)}


@pytest.mark.parametrize("day", DAYS, ids=lambda d: d.name)
def test_daily_max_min_reproduce_source(day):
    s = STATED[day.name]
    assert day.temp_max - C0 == pytest.approx(s["tmax"], abs=1e-9)
    assert day.temp_min - C0 == pytest.approx(s["tmin"], abs=1e-9)
    rise, _, sset = day.sun_times()
    # analytic extremes of Parton & Logan: min at sunrise + c, max at sunrise + c + (Y+2a)/2
    t_min = rise + cl.PL_C
    t_max = t_min + (sset - rise + 2 * cl.PL_A) / 2
    assert day.temp_air(t_min) - C0 == pytest.approx(s["tmin"], abs=1e-9)
    assert day.temp_air(t_max) - C0 == pytest.approx(s["tmax"], abs=1e-9)
    h = np.arange(0, 24, 1 / 60)
    temps = day.temp_air(h)
    assert temps.max() <= day.temp_max + 1e-9 and temps.min() >= day.temp_min - 1e-9
    assert 13.0 < t_max < 15.0           # maximum in the early afternoon
    # continuous (no jump at sunrise/sunset or midnight): max step per minute small
    assert np.max(np.abs(np.diff(np.append(temps, temps[0])))) < 0.05


@pytest.mark.parametrize("day", DAYS, ids=lambda d: d.name)
def test_daily_mean_close_to_stated_mean(day):
    # The source's monthly mean is an independent statistic (not an input). The shape
    # model fixed by Tmin/Tmax must reproduce it within 10 % of the daily range
    # (Parton & Logan's coefficients were fitted elsewhere; measured: +0.43 K summer,
    # -0.21 K winter).
    h = np.arange(0, 24, 1 / 60)
    mean = day.temp_air(h).mean() - C0
    assert abs(mean - STATED[day.name]["tmean"]) < 0.1 * (day.temp_max - day.temp_min)


@pytest.mark.parametrize("day", DAYS, ids=lambda d: d.name)
def test_humidity_and_cloud_reproduce_source(day):
    s = STATED[day.name]
    h = np.arange(0, 24, 0.1)
    rh = day.relative_humidity(h)
    assert rh.mean() == pytest.approx(s["rh"], abs=0.05)
    assert np.all(rh <= 100) and rh.max() > rh.min()      # RH follows the temperature cycle
    # cloud = 1 - sunshine / day length. Day length cross-checked against the textbook
    # sunset hour angle cos(w0) = -tan(phi) tan(delta) (Cooper 1969 declination,
    # +-0.5 deg) plus 2*(0.833 deg refraction + semidiameter)/15 deg/h: within 0.1 h.
    doy = 196 if "summer" in day.name else 15
    decl = np.radians(23.45 * np.sin(2 * np.pi * (284 + doy) / 365))
    lat = np.radians(day.latitude)
    w0 = np.degrees(np.arccos(-np.tan(lat) * np.tan(decl)))
    corr = 2 * np.degrees(np.arcsin(np.sin(np.radians(0.833)) / (np.cos(lat) * np.cos(decl)))) / 15
    assert day.day_length == pytest.approx(2 * w0 / 15 + corr, abs=0.1)
    assert day.cloud_cover == pytest.approx(1 - s["sun"] / day.day_length, abs=1e-12)


def test_sst_annual_harmonic():
    # 2.8 degC (Feb) and 23.6 degC (Aug) -> mean 13.2, amplitude 10.4; mid-July is one
    # month before the peak: 13.2 + 10.4 cos(30 deg) = 22.2067; mid-January one month
    # before the trough: 13.2 - 10.4 cos(30 deg) = 4.1933
    s, w = DAYS
    assert s.temp_sea_mean - C0 == pytest.approx(13.2 + 10.4 * np.cos(np.pi / 6), abs=1e-9)
    assert w.temp_sea_mean - C0 == pytest.approx(13.2 - 10.4 * np.cos(np.pi / 6), abs=1e-9)
    assert cl.annual_harmonic_sst(2.0, 276.0, 297.0) == pytest.approx(276.0)
    assert cl.annual_harmonic_sst(8.0, 276.0, 297.0) == pytest.approx(297.0)
    with pytest.raises(InputError):
        cl.annual_harmonic_sst(7.0, 276.0, 297.0, month_min=2.0, month_max=7.0)


@pytest.mark.parametrize("day", DAYS, ids=lambda d: d.name)
def test_every_number_has_a_labelled_source(day):
    numeric = ["temp_max", "temp_min", "temp_mean_source", "relative_humidity_mean",
               "sunshine_hours", "wind_speed", "wind_direction", "temp_sea_mean",
               "sst_amplitude"]
    assert sorted(day.sources) == sorted(numeric)
    for key, (label, text) in day.sources.items():
        assert label in ("SOURCED", "DERIVED", "ASSUMPTION") and len(text) > 10, key
    table = day.source_table()
    assert "ASSUMPTION" in table and "cloud_cover" in table


@pytest.mark.parametrize("day", DAYS, ids=lambda d: d.name)
def test_weather_record_periodic_and_consistent(day):
    w = day.weather()
    assert w.periodic and len(w.time) == 24 and w.time[0].hour == 0
    h = np.array([0.0, 5.5, 13.7, 23.5])
    s = w.at(h * 3600)
    # hourly sampling + linear interpolation: < 0.1 K from the analytic curve
    np.testing.assert_allclose(s.temp_air, day.temp_air(h), atol=0.1)
    np.testing.assert_allclose(w.at(h * 3600 + 5 * 86400).temp_air, s.temp_air)
    assert w.temp_sea.max() - w.temp_sea.min() == pytest.approx(2 * day.sst_amplitude, abs=1e-3)
    assert w.source.startswith("climatology")


def test_lookup_by_name():
    assert cl.climate_day("summer").name == "dalian_summer"
    with pytest.raises(InputError, match="climatology"):
        cl.climate_day("monsoon")
    assert sun.sunrise_sunset("2023-07-15", 38.91, 121.63, "Etc/GMT-8")[0] < 5.0
