"""Sky long-wave: humidity formulas, clear-sky emissivity models, cloud corrections."""

import numpy as np
import pytest

from shipthermal.environment import sky
from shipthermal.errors import InputError
from shipthermal.units import SIGMA

T = np.array([263.15, 273.15, 283.15, 293.15, 303.15])


def test_saturation_vapour_pressure_vs_iapws():
    # IAPWS-95 / Wagner & Pruss (2002) saturation pressures over water:
    # 0 degC 611.2 Pa, 20 degC 2339.2 Pa, 30 degC 4246.9 Pa. Alduchov & Eskridge (1996)
    # state < 0.4 % relative error for their Magnus fit: tolerance 0.4 %.
    np.testing.assert_allclose(sky.saturation_vapour_pressure([273.15, 293.15, 303.15]),
                               [611.2, 2339.2, 4246.9], rtol=4e-3)


def test_dew_point_round_trip():
    rh = np.array([20.0, 50.0, 80.0, 100.0, 100.0])
    td = sky.dew_point(T, rh)
    np.testing.assert_allclose(td[-2:], T[-2:], atol=1e-9)  # saturated: Td = T
    np.testing.assert_allclose(sky.relative_humidity_from_dew_point(T, td), rh, rtol=1e-12)
    assert np.all(td <= T + 1e-12)


def test_brutsaert_hand_value():
    # 1.24 (e/T)^(1/7) with e = 10 hPa, T = 288.15 K: ln(10/288.15) = -3.360896,
    # /7 = -0.480128, exp = 0.618704, x 1.24 = 0.767193 (step by step, 6 digits)
    assert abs(sky.emissivity_brutsaert(288.15, 1000.0) - 0.767193) < 2e-6


def test_prata_dry_limit_and_hand_value():
    # w -> 0: eps = 1 - exp(-sqrt(1.2)) = 1 - exp(-1.095445) = 1 - 0.334391 = 0.665609
    assert abs(sky.emissivity_prata(288.15, 0.0) - 0.665609) < 1e-6
    # e = 10 hPa, T = 288.15: w = 46.5*10/288.15 = 1.613743 cm;
    # sqrt(1.2 + 3w) = sqrt(6.041229) = 2.457891; exp(-2.457891) = 0.0856153;
    # 1 - 2.613743*0.0856153 = 0.776224
    assert abs(sky.emissivity_prata(288.15, 1000.0) - 0.776224) < 2e-6


def test_swinbank_published_constant():
    # Swinbank (1963): L = 5.31e-13 T^6; at 300 K: 5.31e-13 * 7.29e14 = 387.099 W/m2
    assert abs(sky.longwave_down(300.0, 50.0, 0.0, clear_model="swinbank") - 387.099) < 1e-3


def test_clear_sky_models_agree_for_moist_air():
    # Prata (1996) finds Brutsaert and his formula within ~10 W/m2 rms at
    # humid mid-latitude sites: at RH 70 %, 270-300 K the emissivities must agree to
    # 0.06 (~ 20 W/m2 at 330 W/m2) and both grow with humidity and temperature.
    t = np.array([270.0, 280.0, 290.0, 300.0])
    e = 0.7 * sky.saturation_vapour_pressure(t)
    b, p = sky.emissivity_brutsaert(t, e), sky.emissivity_prata(t, e)
    assert np.max(np.abs(b - p)) < 0.06
    assert np.all(np.diff(b) > 0) and np.all(np.diff(p) > 0)
    assert np.all(sky.emissivity_brutsaert(290.0, [500, 1000, 2000]) < 1)


@pytest.mark.parametrize("model", ["unsworth_monteith", "crawford_duchon"])
def test_cloud_corrections_limits_and_monotonic(model):
    eps0 = np.full(11, 0.75)
    c = np.linspace(0, 1, 11)
    eps = sky.cloud_correction(eps0, c, model)
    assert eps[0] == pytest.approx(0.75)
    assert np.all(np.diff(eps) > 0)
    # overcast: Unsworth & Monteith 0.84 + 0.16 eps_clr; Crawford & Duchon: 1
    assert eps[-1] == pytest.approx(0.84 + 0.16 * 0.75 if model == "unsworth_monteith" else 1.0)


def test_longwave_measured_overrides_and_sky_temperature():
    t = np.array([290.0, 290.0])
    meas = np.array([np.nan, 350.0])
    lw = sky.longwave_down(t, 70.0, 0.3, measured=meas)
    eps = sky.sky_emissivity(290.0, 70.0, 0.3)
    assert lw[1] == 350.0
    assert lw[0] == pytest.approx(eps * SIGMA * 290.0 ** 4, rel=1e-12)
    assert sky.sky_temperature(lw[0]) == pytest.approx(eps ** 0.25 * 290.0, rel=1e-12)


def test_unknown_models_rejected():
    with pytest.raises(InputError, match="clear_model"):
        sky.sky_emissivity(290.0, 50.0, clear_model="idso")
    with pytest.raises(InputError, match="cloud_model"):
        sky.cloud_correction(0.7, 0.5, "kimball")
