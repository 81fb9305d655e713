"""Sea: diurnal SST, Fresnel emissivity, sea-leaving long-wave, sea albedo."""

import numpy as np
import pytest

from shipthermal import optics
from shipthermal.environment import sea
from shipthermal.units import SIGMA


def test_sst_diurnal_mean_and_peak():
    h = np.arange(0, 24, 0.25)
    t = sea.sst_diurnal(h, 290.0, 0.2, 14.0)
    assert t.mean() == pytest.approx(290.0, abs=1e-12)   # full periods: exact mean
    assert h[np.argmax(t)] == 14.0 and t.max() == pytest.approx(290.2)
    np.testing.assert_allclose(sea.sst_diurnal(h + 24, 290.0, 0.2), sea.sst_diurnal(h, 290.0, 0.2))


def test_fresnel_nadir_and_grazing():
    n, k = 1.218, 0.0508
    nadir = 1 - ((n - 1) ** 2 + k ** 2) / ((n + 1) ** 2 + k ** 2)
    assert optics.sea_emissivity_angular(0.0) == pytest.approx(nadir, abs=1e-12)
    assert optics.sea_emissivity_angular(0.0, complex(1.5, 0)) == pytest.approx(0.96, abs=1e-12)
    eps = optics.sea_emissivity_angular(np.linspace(0, 89.999, 50))
    assert np.all(np.diff(eps) < 0) and eps[-1] < 1e-3


@pytest.mark.parametrize("n", [1.33, 1.5, 2.0])
def test_hemispherical_emissivity_vs_dunkle_closed_form(n):
    # Dunkle (1963) closed form of the hemispherical emissivity of a smooth dielectric
    # (Siegel & Howell, Thermal Radiation Heat Transfer): independent of our angular
    # Fresnel code and quadrature. Midpoint rule with 2000 steps: error ~1e-7.
    d = (0.5 - (3 * n + 1) * (n - 1) / (6 * (n + 1) ** 2)
         - n ** 2 * (n ** 2 - 1) ** 2 / (n ** 2 + 1) ** 3 * np.log((n - 1) / (n + 1))
         + 2 * n ** 3 * (n ** 2 + 2 * n - 1) / ((n ** 2 + 1) * (n ** 4 - 1))
         - 8 * n ** 4 * (n ** 4 + 1) / ((n ** 2 + 1) * (n ** 4 - 1) ** 2) * np.log(n))
    assert optics.sea_emissivity_hemispherical(complex(n, 0)) == pytest.approx(d, abs=1e-6)


def test_flat_water_hemispherical_below_measured_sea():
    # Flat water at 10 um: ~0.95; the measured broadband sea value (Konda et al. 1994,
    # 0.984) is higher (roughness, band, and a sky warmest near the horizon where the sea
    # reflects most). Both must be in (0.9, 1).
    flat = optics.sea_emissivity_hemispherical()
    assert 0.93 < flat < sea.SEA_EMISSIVITY < 1.0


def test_sea_longwave_up_limits():
    assert sea.sea_longwave_up(290.0, 300.0, 1.0) == pytest.approx(SIGMA * 290.0 ** 4)
    assert sea.sea_longwave_up(0.0, 300.0, 0.9) == pytest.approx(30.0)
    # sea at sky temperature radiates like the sky: energy neutral
    tsky = (350.0 / SIGMA) ** 0.25
    assert sea.sea_longwave_up(tsky, 350.0, 0.98) == pytest.approx(350.0)


def test_taylor_albedo_values():
    # Taylor et al. (1996) eq. A1: 0.037 / (1.1 mu^1.4 + 0.15)
    assert sea.sea_albedo_direct(0.0) == pytest.approx(0.037 / 1.25)
    assert sea.sea_albedo_direct(60.0) == pytest.approx(0.037 / (1.1 * 0.5 ** 1.4 + 0.15))
    assert sea.sea_albedo_direct(90.0) == pytest.approx(0.037 / 0.15)
    assert np.all(np.diff(sea.sea_albedo_direct(np.linspace(0, 90, 91))) > 0)
    up = sea.sea_reflected_shortwave(800.0, 100.0, 60.0)
    assert up == pytest.approx(sea.sea_albedo_direct(60.0) * 400.0 + 6.0)
    assert sea.sea_reflected_shortwave(800.0, 100.0, 95.0) == pytest.approx(6.0)


def test_environment_sea_follows_the_wind_by_default():
    from shipthermal.environment import Environment, climate_day

    day = climate_day("winter")
    st = Environment.from_climate_day(day).at([0.0, 12 * 3600.0])
    want = optics.sea_emissivity_rough(st.wind_speed)
    np.testing.assert_allclose(st.sea_emissivity, want, rtol=1e-12)
    assert np.all((want > 0.947) & (want < 0.967))   # the table's calm and 20 m/s ends
    # the sea radiates from its skin (bulk SST + warm layer - cool skin)
    np.testing.assert_allclose(st.sea_longwave_up,
                               sea.sea_longwave_up(st.temp_sea_skin, st.longwave_down, want))
    fixed = Environment.from_climate_day(day, sea_emissivity=0.984).at([0.0])
    assert fixed.sea_emissivity == 0.984


def test_rough_sea_table_monotone_between_flat_and_one():
    t = np.array(optics.ROUGH_SEA_HEMISPHERICAL_EMISSIVITY)
    assert np.all(np.diff(t) > 0) and t[-1] < 1.0
    assert optics.sea_emissivity_rough(-1.0) == t[0]
