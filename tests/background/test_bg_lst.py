"""Single-channel LST: atmospheric functions, emissivity, RTE inversion."""

import numpy as np
import pytest

from imaging.background.lst import (JIMENEZ_MUNOZ_2014_B10, at_sensor_radiance, atmospheric_functions,
                                    emissivity_ndvi_threshold, lst_single_channel, ndvi)
from imaging.background.synthetic import LANDSAT8_B10
from shipthermal.errors import InputError

K1, K2 = LANDSAT8_B10["k1"], LANDSAT8_B10["k2"]


def test_psi_functions_by_hand():
    # JM2014 Table I at w = 2 g cm-2, evaluated by hand:
    # psi1 = 0.04019*4 + 0.02916*2 + 1.01523 = 1.23431
    # psi2 = -0.38333*4 - 1.50294*2 + 0.20324 = -4.33596
    # psi3 = 0.00918*4 + 1.36072*2 - 0.27514 = 2.48302
    atm = atmospheric_functions(2.0)
    np.testing.assert_allclose(atm.psi, [1.23431, -4.33596, 2.48302], atol=1e-12)
    # psi1 = 1/tau, psi3 = L_down, psi2 = -L_down - L_up/tau
    assert atm.tau == pytest.approx(1 / 1.23431)
    assert atm.l_down == pytest.approx(2.48302)
    assert -atm.l_down - atm.l_up / atm.tau == pytest.approx(-4.33596)
    assert JIMENEZ_MUNOZ_2014_B10.shape == (3, 3)


@pytest.mark.parametrize("w", [0.1, 6.5, float("nan")])
def test_water_vapour_out_of_range(w):
    with pytest.raises(InputError, match="water_vapour"):
        atmospheric_functions(w)


def test_emissivity_ndvi_thresholds_by_hand():
    red = np.array([0.2, 0.1, 0.1, 0.05, 0.03])
    v = np.array([0.1, 0.35, 0.5, 0.8, -0.2])
    eps = emissivity_ndvi_threshold(v, red)
    # soil: 0.979 - 0.035*0.2 = 0.972
    # mixed at NDVI 0.35: Pv = 0.25 -> 0.99*0.25 + 0.97*0.75 + 0.03*0.99*0.55*0.75 = 0.98725125
    # NDVI 0.5 (upper edge of mixed, Pv = 1): 0.99; full vegetation 0.99; water 0.991
    np.testing.assert_allclose(eps, [0.972, 0.98725125, 0.99, 0.99, 0.991], atol=1e-12)
    assert ndvi(0.1, 0.3) == pytest.approx(0.5)


@pytest.mark.parametrize("w", [0.5, 1.5, 3.0, 5.0])
def test_rte_inversion_is_exact(w):
    # planck method: the inversion of the forward RTE must return the input to round-off
    # (1e-8 K ~ float64 precision of a Planck round trip).
    rng = np.random.default_rng(3)
    temps = rng.uniform(250, 330, 200)
    eps = rng.uniform(0.95, 1.0, 200)
    atm = atmospheric_functions(w)
    rad = at_sensor_radiance(temps, eps, atm, K1, K2)
    np.testing.assert_allclose(lst_single_channel(rad, eps, atm, K1, K2), temps, atol=1e-8)


def test_taylor_form_error_small_and_growing():
    # JM2014's gamma/delta form linearises Planck around T_sen: exact as T_s -> T_sen, error
    # growing with |T_s - T_sen|. At w = 1 g cm-2 and T_s - T_sen < 4.1 K it stays below
    # 0.15 K (measured 0.03..0.11 K), far inside the method's ~1.5 K overall accuracy.
    from imaging.background.landsat import radiance_to_brightness_temperature
    atm = atmospheric_functions(1.0)
    temps = np.array([290.0, 300.0, 310.0, 320.0])
    rad = at_sensor_radiance(temps, 0.98, atm, K1, K2)
    err = lst_single_channel(rad, 0.98, atm, K1, K2, method="taylor") - temps
    dt = temps - radiance_to_brightness_temperature(rad, K1, K2)
    assert np.all(np.abs(err) < 0.15)
    assert np.all(np.diff(dt) > 0) and np.all(np.diff(err) > 0)


def test_bad_emissivity_rejected():
    atm = atmospheric_functions(1.0)
    with pytest.raises(InputError, match="emissivity"):
        lst_single_channel(np.array([9.0]), np.array([1.2]), atm, K1, K2)
    with pytest.raises(InputError, match="lst_method"):
        lst_single_channel(np.array([9.0]), np.array([0.9]), atm, K1, K2, method="split")
