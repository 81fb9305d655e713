"""Rough-sea emissivity: closes with the Cox-Munk reflectance; one sea for both stages."""

import math

import numpy as np
import pytest

from shipthermal.optics import brdf as B
from imaging.radiometry import (ROUGH_SEA_QUADRATURE, rough_sea_emissivity,
                                rough_sea_emissivity_hemispherical, sea_emissivity,
                                water_band_mean_index)
from imaging.scene import background_optics
from shipthermal import optics

BANDS = ("3-5", "8-14")
ANGLES_DEG = (0.0, 30.0, 60.0, 70.0, 75.0, 80.0)


def _albedo_view_quadrature(theta, band, wind):
    """Independent quadrature of the same BRDF: over view directions (not half vectors),
    256 x 256 nodes, another azimuth origin."""
    return B.directional_albedo(B.cox_munk_brdf, theta, 17.0, n_mu=256, n_phi=256,
                                method="view", wind_speed=wind,
                                refractive_index=water_band_mean_index(band),
                                shadowing=True)


@pytest.mark.parametrize("band", BANDS)
@pytest.mark.parametrize("wind", [2.0, 5.0, 12.0])
def test_emissivity_plus_albedo_closes_up_to_80_deg(band, wind):
    # Required <= 0.5 %; measured |eps + a - 1| < 4e-5 (the two quadratures differ). The
    # flat Fresnel emissivity with the same reflectance misses by 5 % at 75 deg, 13 % at 80.
    worst_flat = 0.0
    for deg in ANGLES_DEG:
        th = deg
        a = _albedo_view_quadrature(th, band, wind)
        eps = float(rough_sea_emissivity(th, band, wind))
        assert eps + a == pytest.approx(1.0, abs=1e-3), (deg, eps, a)
        worst_flat = max(worst_flat, abs(float(sea_emissivity(th, band)) + a - 1.0))
    assert worst_flat > 0.03  # the check can tell the flat emissivity apart


@pytest.mark.parametrize("band", BANDS)
def test_rough_emissivity_limits(band):
    th = np.array([0.0, 60.0, 75.0, 80.0])
    flat = sea_emissivity(th, band)
    calm, windy = rough_sea_emissivity(th, band, 1.0), rough_sea_emissivity(th, band, 10.0)
    # near nadir the slopes hardly matter (first order in the slope variance)
    assert calm[0] == pytest.approx(flat[0], abs=2e-4)
    assert windy[0] == pytest.approx(flat[0], abs=1e-3)
    # at large angles slopes raise the emissivity, more with more wind (Masuda et al. 1988)
    assert np.all(windy[2:] > calm[2:]) and np.all(calm[2:] > flat[2:])
    assert np.all((windy > 0.5) & (windy < 1.0))
    # same function behind both entry points
    assert np.array_equal(sea_emissivity(th, band, wind_speed=10.0), windy)


def test_quadrature_converged():
    n_mu, n_phi = ROUGH_SEA_QUADRATURE
    m = water_band_mean_index("8-14")
    for deg, wind in ((80.0, 1.0), (60.0, 5.0), (85.0, 15.0)):
        fine = B.directional_albedo(B.cox_munk_brdf, deg, n_mu=2 * n_mu,
                                    n_phi=2 * n_phi, method="half", wind_speed=wind,
                                    refractive_index=m, shadowing=True)
        eps = float(rough_sea_emissivity(deg, "8-14", wind))
        assert 1.0 - eps == pytest.approx(fine, abs=1e-4), (deg, wind)


def test_thermal_stage_table_is_the_imaging_model():
    nodes = np.array(optics.ROUGH_SEA_WIND_NODES)
    table = np.array(optics.ROUGH_SEA_HEMISPHERICAL_EMISSIVITY)
    for u in (0.0, 13.0):
        k = int(np.flatnonzero(nodes == u)[0])
        assert table[k] == pytest.approx(rough_sea_emissivity_hemispherical("8-14", u),
                                         abs=6e-6)  # stored to 1e-5
    # between nodes (measured < 1e-4 off the model)
    assert float(optics.sea_emissivity_rough(4.5)) == pytest.approx(
        rough_sea_emissivity_hemispherical("8-14", 4.5), abs=1e-4)
    assert float(optics.sea_emissivity_rough(35.0)) == table[-1]
    # flat limit: the flat-water hemispherical value with the same band-mean index
    flat = optics.sea_emissivity_hemispherical(water_band_mean_index("8-14"))
    assert table[0] == pytest.approx(flat, abs=3e-3)


def test_hemispherical_quadrature_converged():
    assert rough_sea_emissivity_hemispherical("3-5", 5.0) == pytest.approx(
        rough_sea_emissivity_hemispherical("3-5", 5.0, n_nodes=48), abs=2e-5)


@pytest.mark.parametrize("band", BANDS)
def test_scene_water_uses_rough_emissivity_and_keeps_kirchhoff_on_override(band):
    o = background_optics(band, 70.0, 30.0, 7.0)
    rough = float(rough_sea_emissivity(70.0, band, 7.0))
    assert o.emissivity[1] == rough and o.water_sun_scale == 1.0
    o2 = background_optics(band, 70.0, 30.0, 7.0, emissivity_override={"water": 0.99})
    assert o2.water_sun_scale == pytest.approx(0.01 / (1.0 - rough))
