"""Off-nadir viewing end to end: slant path, rough-sea emissivity and glint at the view angle."""

import math

import numpy as np
import pytest

from shipthermal.optics import brdf as B
from imaging.atmosphere import atmosphere, planck_weighted_transmittance
from imaging.radiometry import band_radiance, water_band_mean_index
from imaging.render import SceneRenderer, conditions_from_atmosphere
from imaging.scene import GriddedBackground, ShipPlacement, compass_to_math_azimuth
from imaging.thermal_history import ShipThermalHistory
from shipthermal.raytrace.scenes import box

RES, WIND, T_SEA = 30.0, 6.0, 293.0
SUN_ZENITH, SUN_AZIMUTH = 35.0, 180.0     # sun in the south
VIEW_AZIMUTH = 0.0                        # sensor in the north: glint near 35 deg


def _pixel_radiance(band, view_zenith):
    V, F = box([100.0, 100.0, -1.0], [130.0, 110.0, 6.0])
    m = len(F)
    hist = ShipThermalHistory(V, F, np.zeros(m, int), ("deck",), [0.0, 3600.0],
                              np.full((2, m), 300.0))
    bg = GriddedBackground.uniform((8, 8), 1, T_SEA, RES)
    r = SceneRenderer(hist, bg, ShipPlacement(0.0, 0.0, 90.0), view_zenith_deg=view_zenith,
                      view_azimuth_deg=VIEW_AZIMUTH, samples_per_pixel=4, wind_speed=WIND)
    cond = conditions_from_atmosphere("summer", band, view_zenith, VIEW_AZIMUTH, SUN_ZENITH,
                                      SUN_AZIMUTH)
    fr = r.render(cond, hist.at(0.0), np.full((8, 8), T_SEA))
    assert fr.coverage[7, 0] == 0.0 and fr.shadow[7, 0] == 0.0   # open water corner
    return float(fr.radiance[7, 0])


def _independent(band, view_zenith):
    """Eqs. 1-2 for open water from the atmosphere and BRDF functions directly; the
    emissivity as one minus an albedo integrated over view directions (the product
    integrates over half vectors)."""
    th_v = view_zenith
    m = water_band_mean_index(band)
    eps = 1.0 - B.directional_albedo(B.cox_munk_brdf, th_v, 0.0, n_mu=256, n_phi=256,
                                     method="view", wind_speed=WIND, refractive_index=m,
                                     shadowing=True)
    rel = (VIEW_AZIMUTH - SUN_AZIMUTH + 180.0) % 360.0 - 180.0
    atm = atmosphere("summer", band, view_zenith, SUN_ZENITH, view_azimuth_from_sun_deg=rel)
    f = float(B.cox_munk_brdf(SUN_ZENITH, float(compass_to_math_azimuth(
        SUN_AZIMUTH)), th_v, float(compass_to_math_azimuth(VIEW_AZIMUTH)), WIND, m,
        shadowing=True))
    tau_e = float(planck_weighted_transmittance("summer", band, view_zenith, T_SEA))
    sun = atm.solar_irradiance_ground * math.cos(math.radians(SUN_ZENITH)) * f
    # each reflected term through the transmittance of its own spectrum
    sky = (1.0 - eps) * (atm.transmittance_sky_weighted * atm.sky_radiance
                         + atm.transmittance_sky_solar_weighted * atm.sky_radiance_solar)
    return (tau_e * eps * band_radiance(T_SEA, band) + sky
            + atm.transmittance_solar_weighted * sun + atm.path_radiance), atm, sun


@pytest.mark.parametrize("band", ["3-5", "8-14"])
def test_water_pixel_matches_eqs_1_2_at_every_view_angle(band):
    out = {}
    for vz in (0.0, 30.0, 45.0, 60.0):
        want, atm, sun = _independent(band, vz)
        got = _pixel_radiance(band, vz)
        # float32 image (6e-8), the renderer's 0.5 K Planck-weighted transmittance table
        # (< 1e-5) and the two albedo quadratures (< 4e-5 in emissivity)
        assert got == pytest.approx(want, rel=2e-4), (band, vz)
        out[vz] = (got, atm.transmittance, atm.path_radiance_thermal, sun)
    # the slant path: less transmittance, more path radiance off nadir
    assert out[0.0][1] > out[30.0][1] > out[60.0][1]
    assert out[0.0][2] < out[30.0][2] < out[60.0][2]
    # the glint follows the view: strongest near the sun's specular direction (35 deg)
    assert out[30.0][3] > 10.0 * out[0.0][3] and out[30.0][3] > out[60.0][3]
