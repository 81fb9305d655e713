"""Atmosphere from the embedded tables: six LOWTRAN 7 models, the day's state, cloud decks,
scattered sunlight, named and user bands (no Fortran needed)."""

import numpy as np
import pytest

from imaging.atmosphere import (MODEL_NAMES, AtmosphereState, atmosphere, band_integrate,
                                interpolation_errors, load_table, model_for_site,
                                planck_weighted_transmittance, sky_radiance, surface_state)
from imaging.atmosphere import core
from imaging.atmosphere import models as mdl
from imaging.atmosphere import tables as tb
from imaging.radiometry import planck_radiance
from shipthermal.optics.responses import BAND_NAMES, named_band
from shipthermal.errors import InputError

BANDS = ("3-5", "8-14")


def _band(model, band, view, sun=30.0, **kw):
    return atmosphere(model, band, view, sun, spectral=False, **kw)


# ---------------------------------------------------------------- table structure
@pytest.mark.parametrize("model", MODEL_NAMES)
def test_table_reproduces_grid_nodes_exactly(model):
    t = load_table()
    for band in ("3-5", "8-14", "landsat8_tirs_b10"):
        ib = t.band_index(band)
        i0 = int(np.flatnonzero(t.grid("state_temp_offset_K") == 0.0)[0])
        j1 = int(np.argmin(np.abs(t.get(model, "state_rh") - surface_state(model).rel_humidity)))
        # the model's own state is a node of the temperature x water grid (default wind),
        # stored exactly as the reference of the int16 steps
        node = t.get(model, "state_ref")[ib]
        np.testing.assert_allclose(t.state(model, "thermal_t")[i0, j1, ib], node, rtol=1e-12)
        for q in tb.THERMAL_QUANTITIES:
            axis = tb._AXIS_OF[q]
            for k, z in enumerate(t.grid(axis)):
                got = float(core.band_value(model, band, q, z))
                assert got == pytest.approx(node[tb.columns(q)][k], rel=1e-12, abs=1e-15), \
                    (band, q, z)


def test_tables_hold_every_model_and_named_band():
    t = load_table()
    assert tuple(t.meta["models"]) == MODEL_NAMES
    assert t.bands == BAND_NAMES
    assert t.meta["format"] == tb.FORMAT


@pytest.mark.parametrize("model", MODEL_NAMES)
def test_stated_interpolation_errors_are_small(model):
    """The errors the generator measured against live LOWTRAN (a regression guard on the
    shipped file). Measured maxima: geometry at the model's own state, transmittance
    ≤ 2.4e-3 absolute (tropical 8-14 um at 77 deg), path and sky radiance ≤ 0.46 %, direct
    sun ≤ 0.75 % of the overhead sun's; the day's state (40 days incl. the corners of
    ±12 K, RH 40-95 %, wind 0-18 m/s) ≤ 4.7 % (3-5 um direct sun; sub-arctic winter
    Landsat band 10 path / sky 4.4 %); cloud decks ≤ 0.07 %."""
    err = interpolation_errors()[model]
    for band, qs in err["geometry"].items():
        assert qs["transmittance"]["abs"] < 3e-3, band
        for q in ("path_radiance", "sky_radiance"):
            assert qs[q]["rel"] < 5e-3, (band, q)
        e0 = float(core.band_value(model, band, "solar_irradiance", 0.0))
        assert qs["solar_irradiance"]["abs"] < 1e-2 * e0, band
    for band, qs in err["state"].items():
        for q, e in qs.items():
            assert e["rel"] < 5e-2, (band, q, e)
    for band, decks in err["cloud"].items():
        for deck, e in decks.items():
            assert e["rel"] < 1e-3, (band, deck, e)


# ---------------------------------------------------------------- physics checks
@pytest.mark.parametrize("model", MODEL_NAMES)
@pytest.mark.parametrize("band", BANDS)
def test_monotonic_in_view_and_sun_zenith(model, band):
    v = np.linspace(0.0, 80.0, 41)
    tau = core.band_value(model, band, "transmittance", v)
    assert np.all(np.diff(tau) < 0)
    # the path radiance grows with the path to 60 deg; beyond, in the humid models' 3-5 um,
    # the longer path sees colder, higher layers and it falls again (LOWTRAN's own nodes)
    lp = core.band_value(model, band, "path_radiance", v[v <= 60.0])
    assert np.all(np.diff(lp) > 0)
    e = core.band_value(model, band, "solar_irradiance", np.linspace(0.0, 90.0, 46))
    assert np.all(np.diff(e) <= 0) and e[-1] == 0.0
    sky = sky_radiance(model, band, np.linspace(0.0, 89.0, 45))
    assert np.all(np.diff(sky) > 0)


@pytest.mark.parametrize("view", [0.0, 30.0, 60.0])
def test_moist_warm_models_more_opaque_in_lwir(view):
    tau = {m: _band(m, "8-14", view).transmittance for m in MODEL_NAMES}
    assert tau["tropical"] < tau["midlatitude_summer"] < tau["us_standard_1976"]
    assert tau["midlatitude_summer"] < tau["midlatitude_winter"] < tau["subarctic_winter"]


def test_paper_labels_are_the_midlatitude_models():
    a = _band("summer", "8-14", 20.0)
    b = _band("midlatitude_summer", "8-14", 20.0)
    assert a.season == b.season == "summer" and a.model == "midlatitude_summer"
    assert a.transmittance == b.transmittance and a.sky_radiance == b.sky_radiance
    assert _band(3, "8-14", 20.0).season == "winter"


@pytest.mark.parametrize("model", MODEL_NAMES)
def test_own_state_is_the_default(model):
    s = surface_state(model)
    own = AtmosphereState(temp_air_K=s.temp_air_K, rel_humidity=s.rel_humidity,
                          wind_speed=mdl.default_wind_speed(model))
    a, b = _band(model, "8-14", 30.0), _band(model, "8-14", 30.0, state=own)
    for f in ("transmittance", "path_radiance", "sky_radiance", "solar_irradiance_ground"):
        assert getattr(b, f) == pytest.approx(getattr(a, f), rel=1e-9), f


def test_state_moves_the_atmosphere_the_right_way():
    s = surface_state("midlatitude_summer")
    base = _band("mls", "8-14", 30.0)
    moist = _band("mls", "8-14", 30.0, state=AtmosphereState(rel_humidity=95.0))
    warm = _band("mls", "8-14", 30.0, state=AtmosphereState(temp_air_K=s.temp_air_K + 8.0))
    assert moist.transmittance < base.transmittance and moist.sky_radiance > base.sky_radiance
    assert warm.sky_radiance > base.sky_radiance
    # more wind: more sea salt, lower 3-5 um transmittance and more scattered sunlight
    calm = _band("mls", "3-5", 30.0, state=AtmosphereState(wind_speed=0.0))
    gale = _band("mls", "3-5", 30.0, state=AtmosphereState(wind_speed=18.0))
    assert gale.transmittance < calm.transmittance
    assert gale.path_radiance_solar > calm.path_radiance_solar > 0.0


def test_cloud_share_mixes_the_lowtran_deck():
    clear = _band("mlw", "8-14", 0.0)
    over = _band("mlw", "8-14", 0.0, cloud_cover=1.0, cloud_type="stratus")
    half = _band("mlw", "8-14", 0.0, cloud_cover=0.5, cloud_type="stratus")
    assert half.sky_radiance == pytest.approx(0.5 * (clear.sky_radiance + over.sky_radiance))
    # a low deck (0.33-1 km) radiates nearly as a blackbody at the air temperature: within
    # 15 % of it in 8-14 um, far above the clear sky
    from imaging.radiometry import band_radiance

    b_air = float(band_radiance(surface_state("mlw").temp_air_K, "8-14"))
    assert 0.85 * b_air < over.sky_radiance < b_air
    assert over.sky_radiance > 2.0 * clear.sky_radiance
    # high thin altostratus (2.4-3 km) is colder and lets more of the clear sky show
    alto = _band("mlw", "8-14", 0.0, cloud_cover=1.0, cloud_type="altostratus")
    assert clear.sky_radiance < alto.sky_radiance < over.sky_radiance
    # the cloud share takes away the direct and scattered sunlight
    assert over.solar_irradiance_ground == 0.0 and over.sky_radiance_solar == 0.0


# ---------------------------------------------------------------- scattered sunlight
def test_scattered_sunlight_geometry():
    fwd = _band("mls", "3-5", 40.0, 40.0, sky_zenith_deg=40.0, sky_azimuth_from_sun_deg=5.0)
    side = _band("mls", "3-5", 40.0, 40.0, sky_zenith_deg=40.0, sky_azimuth_from_sun_deg=90.0)
    back = _band("mls", "3-5", 40.0, 40.0, sky_zenith_deg=40.0, sky_azimuth_from_sun_deg=180.0)
    assert fwd.sky_radiance_solar > 5 * side.sky_radiance_solar > 0.0
    assert side.sky_radiance_solar > back.sky_radiance_solar > 0.0
    night = _band("mls", "3-5", 40.0, 100.0)
    assert night.sky_radiance_solar == night.sky_irradiance_solar == 0.0
    assert night.path_radiance == night.path_radiance_thermal
    day = _band("mls", "3-5", 20.0, 35.0)
    assert 0.0 < day.sky_irradiance_solar < day.solar_irradiance_horizontal
    assert 0.0 < day.path_radiance_solar < day.path_radiance_thermal


def test_each_reflected_term_has_its_own_transmittance():
    r = atmosphere("mls", "3-5", 30.0, 40.0)
    lam, tau = r.wavelength_um, r.transmittance_spectral
    e = r.solar_irradiance_spectral
    assert r.transmittance_solar_weighted == pytest.approx(
        band_integrate(lam, tau * e, (3, 5)) / band_integrate(lam, e, (3, 5)), rel=1e-3)
    # the sun's spectrum sits in the 3-4 um window, the thermal sky's in the absorbing
    # 4.3 / 4.5-5 um bands: their transmittances differ by ~2x (the old shortcut used the
    # thermal one for the scattered sunlight)
    assert r.transmittance_sky_weighted < 0.6 * r.transmittance_solar_weighted
    assert r.transmittance_sky_solar_weighted > 1.5 * r.transmittance_sky_weighted
    for f in ("transmittance_sky_mean_weighted", "transmittance_sky_solar_mean_weighted"):
        assert 0.0 < getattr(r, f) < 1.0


def test_planck_weighted_transmittance_matches_the_spectra():
    r = atmosphere("mls", "3-5", 0.0, 30.0)
    lam, tau = r.wavelength_um, r.transmittance_spectral
    b = planck_radiance(lam, 300.0)
    direct = band_integrate(lam, tau * b, (3, 5)) / band_integrate(lam, b, (3, 5))
    got = planck_weighted_transmittance("mls", "3-5", 0.0, [300.0, 250.0])
    # the table's 10 K grid with a cubic in T: 1e-4
    assert got[0] == pytest.approx(direct, rel=1e-4)
    assert got[0] < r.transmittance - 0.03
    assert planck_weighted_transmittance("mls", "3-5", 0.0, 2000.0) > got[0]


# ---------------------------------------------------------------- bands
def test_user_response_equal_to_a_named_band_gives_its_values():
    resp = named_band("landsat8_tirs_b10")
    named = _band("mls", "landsat8_tirs_b10", 20.0)
    user = _band("mls", "l8", 20.0, response=(resp.wavelength_um, resp.response))
    for f in ("transmittance", "path_radiance_thermal", "sky_radiance",
              "transmittance_sky_weighted"):
        assert getattr(user, f) == pytest.approx(getattr(named, f), rel=2e-3), f


@pytest.mark.parametrize("band", BAND_NAMES)
def test_every_named_band_is_served(band):
    r = _band("tropical", band, 10.0, 40.0)
    assert 0.0 < r.transmittance < 1.0 and r.path_radiance > 0.0 and r.sky_radiance > 0.0


# ---------------------------------------------------------------- site rule
@pytest.mark.parametrize("lat, month, expected", [
    (0.0, 1, "tropical"), (38.9, 7, "midlatitude_summer"), (38.9, 1, "subarctic_summer"),
    (60.0, 1, "midlatitude_winter"), (-48.0, 7, "midlatitude_winter"),
    (52.0, 8, "subarctic_summer"), (64.0, 12, "midlatitude_winter")])
def test_site_rule_latitude_month_table(lat, month, expected):
    assert model_for_site(lat, month) == expected


def test_site_rule_day_temperature_picks_the_closest_model():
    assert model_for_site(53.4, 9, 287.0) == "subarctic_summer"
    assert model_for_site(53.4, 9, 289.0) == "us_standard_1976"
    assert model_for_site(25.0, 7, 303.0) == "tropical"
    assert model_for_site(60.0, 1, 250.0) == "subarctic_winter"
    with pytest.raises(InputError) as exc:
        model_for_site(40.0, 1, 230.0)
    assert "257.2" in str(exc.value)


# ---------------------------------------------------------------- bad input
@pytest.mark.parametrize("kwargs, field", [
    (dict(model="arctic", band="8-14"), "model"),
    (dict(model="mls", band="1-2"), "band"),
    (dict(model="mls", band="8-14", cloud_cover=1.0, cloud_type="cirrus"), "cloud_type"),
    (dict(model="mls", band="8-14", view_zenith_deg=85.0), "view_zenith_deg"),
    (dict(model="mls", band="8-14", backend="modtran"), "backend"),
    (dict(model="mls", band="8-14", aerosol={"vis_km": 10.0}), "vis_km"),
])
def test_bad_input_names_the_field_and_the_allowed(kwargs, field):
    args = dict(view_zenith_deg=0.0, sun_zenith_deg=0.0)
    args.update(kwargs)
    with pytest.raises(InputError) as exc:
        atmosphere(**args)
    assert exc.value.field == field
    if field == "model":
        assert all(m in str(exc.value) for m in MODEL_NAMES)


def test_band_integrate_exact_for_linear_spectra():
    lam = np.linspace(2.9, 14.5, 37)
    v = 2.0 + 0.5 * lam
    exact = 2.0 * 6.0 + 0.25 * (14.0 ** 2 - 8.0 ** 2)
    assert band_integrate(lam, v, (8.0, 14.0)) == pytest.approx(exact, rel=1e-12)
    assert band_integrate(lam, v, (8.0, 14.0), mean=True) == pytest.approx(exact / 6.0, rel=1e-12)
    resp = (np.array([7.999, 8.0, 14.0, 14.001]), np.array([0.0, 1.0, 1.0, 0.0]))
    assert band_integrate(lam, v, None, response=resp) == pytest.approx(exact, rel=1e-3)
