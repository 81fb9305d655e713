"""Tests for imaging.radiometry: Planck integrals, band quadrature, inverse, emissivities."""

import math

import numpy as np
import pytest
from scipy.integrate import quad

from imaging import radiometry as rad
from shipthermal.optics.brdf import fresnel_reflectance
from shipthermal import optics
from shipthermal.errors import InputError
from shipthermal.units import PLANCK_C1, PLANCK_C2, SIGMA

TEMPS = np.array([150.0, 200.0, 250.0, 273.15, 300.0, 350.0, 450.0, 700.0, 1000.0])

# sigma from the exact SI constants (2 pi^5 k^4 / (15 h^3 c^2)); units.SIGMA is the
# CODATA value rounded to 10 digits (5.670374419e-8), 3.3e-11 below the exact one.
_H, _C, _K = 6.62607015e-34, 299792458.0, 1.380649e-23
SIGMA_EXACT = 2 * math.pi**5 * _K**4 / (15 * _H**3 * _C**2)


def test_full_band_codata_equals_sigma_t4_over_pi_to_round_off():
    # the default constants are 2hc² and hc/k of the exact SI constants
    assert PLANCK_C1 == pytest.approx(2 * _H * _C**2 * 1e24, rel=1e-15)
    assert PLANCK_C2 == pytest.approx(_H * _C / _K * 1e6, rel=1e-15)
    full = rad.band_radiance_rectangular_exact(TEMPS, 0.0, np.inf)
    rel = full / (SIGMA_EXACT * TEMPS**4 / math.pi) - 1
    # both sides are the same closed form evaluated in double precision: a few ulp
    assert np.max(np.abs(rel)) < 1e-14, rel
    # against the rounded units.SIGMA the gap is its rounding, 3.25e-11
    rel_units = full / (SIGMA * TEMPS**4 / math.pi) - 1
    assert np.allclose(rel_units, SIGMA_EXACT / SIGMA - 1, atol=1e-14)


def test_full_band_paper_constants_relative_difference_is_minus_1e_4():
    # cross-check of the paper's eq. 2 constants, c1 = 1.191e8 W um4 m-2 sr-1 and
    # c2 = 1.4388e4 um K: they are the SI ones rounded, 1e-4 apart in the full band
    c1_paper, c2_paper = 1.191e8, 1.4388e4
    full = rad.band_radiance_rectangular_exact(TEMPS, 0.0, np.inf, c1_paper, c2_paper)
    rel = full / (SIGMA_EXACT * TEMPS**4 / math.pi) - 1
    expected = (c1_paper / PLANCK_C1) * (PLANCK_C2 / c2_paper) ** 4 - 1
    # -1.00e-4: c1 rounded to 4 digits gives -3.6e-5, c2 to 5 digits -6.4e-5 (via c2^-4)
    assert expected == pytest.approx(-1.0036e-4, rel=1e-3)
    assert np.allclose(rel, expected, atol=1e-14)


def test_full_band_by_numerical_quadrature_matches_closed_form():
    # independent of the series: scipy quad of the Planck function over (0, inf)
    for t in (200.0, 300.0, 1000.0):
        q = quad(lambda x: x**3 / math.expm1(x) if x > 0 else 0.0, 0.0, 700.0,
                 epsabs=0, epsrel=1e-13, limit=200)[0]
        full = PLANCK_C1 * t**4 / PLANCK_C2**4 * q
        assert full == pytest.approx(SIGMA_EXACT * t**4 / math.pi, rel=1e-12)


@pytest.mark.parametrize("band,lo,hi", [("3-5", 3.0, 5.0), ("8-14", 8.0, 14.0)])
def test_band_radiance_against_adaptive_quadrature(band, lo, hi):
    gl = rad.band_radiance(TEMPS, band)
    series = rad.band_radiance_rectangular_exact(TEMPS, lo, hi)
    ref = np.array([quad(lambda wl: float(rad.planck_radiance(wl, t)), lo, hi,
                         epsabs=0, epsrel=1e-13)[0] for t in TEMPS])
    # series vs quad: two independent exact methods agree to round-off
    assert np.max(np.abs(series / ref - 1)) < 1e-12
    # 8-node Gauss-Legendre: measured 2.2e-12 (3-5) and 1.6e-12 (8-14) worst case
    assert np.max(np.abs(gl / ref - 1)) < 3e-12


def test_band_radiance_user_table_equals_rectangular_when_flat():
    # a 5-knot flat table splits the band into 4 segments: same integral
    resp = rad.SpectralResponse("flat", np.linspace(8, 14, 5), np.ones(5))
    assert np.allclose(rad.band_radiance(TEMPS, resp), rad.band_radiance(TEMPS, "8-14"),
                       rtol=1e-13)


def test_band_radiance_triangular_table_against_quad():
    resp = rad.SpectralResponse("tri", np.array([3.0, 4.0, 5.0]), np.array([0.0, 1.0, 0.0]))
    for t in (250.0, 320.0):
        ref = quad(lambda wl: float(np.interp(wl, resp.wavelength_um, resp.response)
                                    * rad.planck_radiance(wl, t)), 3, 5, points=[4.0],
                   epsabs=0, epsrel=1e-13)[0]
        assert rad.band_radiance(t, resp) == pytest.approx(ref, rel=1e-11)


def test_band_radiance_dt_matches_finite_difference():
    h = 1e-3
    for band in ("3-5", "8-14"):
        fd = (rad.band_radiance(TEMPS + h, band) - rad.band_radiance(TEMPS - h, band)) / (2 * h)
        # central difference error ~ h^2 L'''/6: relative ~1e-8 here
        assert np.allclose(rad.band_radiance_dt(TEMPS, band), fd, rtol=1e-7)


@pytest.mark.parametrize("band", ["3-5", "8-14"])
def test_brightness_temperature_inverts_band_radiance(band):
    temps = np.linspace(120.0, 1200.0, 301)
    back = rad.brightness_temperature(rad.band_radiance(temps, band), band)
    # Newton converges quadratically: 6 steps reach round-off of T (~1e-13 K scale)
    assert np.max(np.abs(back - temps)) < 1e-9


def test_radiance_and_its_derivative_in_one_pass_are_the_separate_ones():
    from shipthermal.optics.planck import _band_sum_and_dt

    for band in ("3-5", "8-14"):
        lum, dlum = _band_sum_and_dt(TEMPS, band, 8, PLANCK_C1, PLANCK_C2)
        np.testing.assert_allclose(lum, rad.band_radiance(TEMPS, band), rtol=1e-14)
        np.testing.assert_allclose(dlum, rad.band_radiance_dt(TEMPS, band), rtol=1e-14)


def test_brightness_temperature_stops_at_round_off():
    """The Newton steps stop once none exceeds 1e-9 K: the temperatures are then exact to
    round-off also through a measured response (the Landsat 8 band 10 table, 800
    quadrature nodes)."""
    from imaging.instruments import instrument

    resp = instrument("landsat8_tirs").band("landsat8_tirs_b10").response
    temps = np.linspace(200.0, 350.0, 151)
    back = rad.brightness_temperature(rad.band_radiance(temps, resp), resp)
    assert np.max(np.abs(back - temps)) < 1e-11


def test_brightness_temperature_of_grey_body_is_lower():
    t = 300.0
    tb = rad.brightness_temperature(0.9 * rad.band_radiance(t, "8-14"), "8-14")
    assert 290 < tb < 300


@pytest.mark.parametrize("band,bound", [("3-5", 5e-7), ("8-14", 3e-9)])
def test_band_radiance_table_error_is_stated_and_true(band, bound):
    table = rad.band_radiance_table(band, 150.0, 450.0, 1.0)
    assert table.max_rel_error < bound
    rng = np.random.default_rng(1)
    t = rng.uniform(150.0, 450.0, 20000)
    err = np.max(np.abs(table(t) / rad.band_radiance(t, band) - 1))
    # the stated error is probed near each midpoint, where the Hermite error peaks; 1 %
    # allows for L'''' varying across an interval (random points may fall between probes)
    assert err <= table.max_rel_error * 1.01


def test_band_radiance_table_rejects_out_of_range():
    table = rad.band_radiance_table("8-14", 200.0, 300.0, 1.0)
    with pytest.raises(InputError, match="temp"):
        table(np.array([150.0]))


def test_spectral_response_validation():
    with pytest.raises(InputError, match="increasing"):
        rad.SpectralResponse("x", np.array([5.0, 3.0]), np.array([1.0, 1.0]))
    with pytest.raises(InputError, match="response"):
        rad.SpectralResponse("x", np.array([3.0, 5.0]), np.array([1.0, 1.5]))
    with pytest.raises(InputError, match="band"):
        rad.standard_band("1-2")


def test_ship_emissivities_come_from_the_parameter_module():
    from shipthermal.parameters import BAND_EMISSIVITY

    for part, bands in BAND_EMISSIVITY.items():
        for band, value in bands.items():
            assert rad.ship_emissivity(part, band) == value
    assert rad.ship_emissivity("hull_dry", "3-5") == BAND_EMISSIVITY["hull"]["3-5"]
    assert rad.ship_emissivity("deck_helipad", "8-14") == BAND_EMISSIVITY["deck"]["8-14"]
    with pytest.raises(InputError, match="part"):
        rad.ship_emissivity("mast", "3-5")


def test_background_emissivities_have_sources_and_bounds():
    for band, classes in rad.BACKGROUND_EMISSIVITY.items():
        assert set(classes) == {"water", "vegetation", "land", "building"}
        for cls, ev in classes.items():
            assert 0.8 < ev.value <= 1.0 and ev.uncertainty > 0 and len(ev.source) > 20
            assert rad.background_emissivity(cls, band) == ev.value


@pytest.mark.parametrize("band", ["3-5", "8-14"])
def test_water_table_entry_is_the_fresnel_value(band):
    computed = float(rad.sea_emissivity(0.0, band))
    # the table is the Fresnel number rounded to 3 digits
    assert rad.BACKGROUND_EMISSIVITY[band]["water"].value == pytest.approx(computed, abs=5e-4)


def test_fresnel_normal_incidence_closed_form_and_grazing_limit():
    m = rad.water_band_mean_index("8-14")
    r0 = ((m.real - 1) ** 2 + m.imag**2) / ((m.real + 1) ** 2 + m.imag**2)
    assert fresnel_reflectance(1.0, m) == pytest.approx(r0, rel=1e-14)
    assert fresnel_reflectance(0.0, m) == pytest.approx(1.0, abs=1e-12)


def test_fresnel_brewster_angle_for_real_index():
    n = 1.5
    tb = math.atan(n)
    ci = math.cos(tb)
    ct = math.sqrt(1 - math.sin(tb) ** 2 / n**2)
    rs = ((ci - n * ct) / (ci + n * ct)) ** 2
    # at Brewster's angle r_p = 0, so the unpolarised value is r_s / 2
    assert fresnel_reflectance(ci, n) == pytest.approx(rs / 2, rel=1e-12)


@pytest.mark.parametrize("band", ["3-5", "8-14"])
def test_sea_emissivity_angular_shape(band):
    theta = np.arange(0, 90, 5.0)
    eps = rad.sea_emissivity(theta, band)
    assert np.all(np.diff(eps) < 0)            # monotone fall toward grazing
    assert 0.97 < eps[0] < 0.99                # nadir water 0.975 (3-5), 0.988 (8-14)
    assert rad.sea_emissivity(90.0, band) == pytest.approx(0.0, abs=1e-9)
    # degrees at the interface: the Fresnel value at the same angle in radians
    m = rad.water_band_mean_index(band)
    np.testing.assert_allclose(eps, 1.0 - fresnel_reflectance(np.cos(np.radians(theta)), m),
                               rtol=1e-14)
    # band-mean index vs Planck-weighted spectral average at 290 K: they differ because
    # Fresnel is nonlinear in (n, k); stated difference < 0.004 at nadir
    spec = rad.sea_emissivity(0.0, band, temp=290.0)
    assert abs(spec - eps[0]) < 0.004


def test_water_index_interpolation_reproduces_table_knots():
    tab = optics.WATER_INDEX_HALE_QUERRY
    m = optics.water_refractive_index(tab[:, 0])
    assert np.array_equal(m.real, tab[:, 1]) and np.array_equal(m.imag, tab[:, 2])
    with pytest.raises(InputError):
        optics.water_refractive_index(1.0)


def test_leaving_radiance_kirchhoff_blackbody_enclosure():
    # In an isothermal enclosure (sky = blackbody at T, no sun) every opaque surface
    # leaves exactly B(T), whatever its emissivity (Kirchhoff).
    b = rad.band_radiance(300.0, "8-14")
    eps = np.array([0.5, 0.78, 0.95, 1.0])
    assert np.allclose(rad.leaving_radiance(b, eps, sky_radiance=b), b, rtol=1e-15)


def test_leaving_radiance_solar_term_and_sun_behind():
    out = rad.leaving_radiance(0.0, 1.0, brdf=0.1, cos_sun_zenith=np.array([0.5, -0.3]),
                               solar_irradiance=20.0)
    assert np.allclose(out, [1.0, 0.0])


def test_gauss_legendre_rule_is_numpys_computed_once_and_read_only():
    """The shared rule equals numpy's leggauss bit for bit, integrates a degree 2n-1
    polynomial exactly, is the same object on every call and cannot be altered in place."""
    from shipthermal.optics.quadrature import gauss_legendre

    x, w = gauss_legendre(8)
    xr, wr = np.polynomial.legendre.leggauss(8)
    assert np.array_equal(x, xr) and np.array_equal(w, wr)
    assert abs(np.sum(w * x**14) - 2.0 / 15.0) < 1e-15     # ∫_{-1}^{1} x^14 dx
    assert gauss_legendre(8)[0] is x
    with pytest.raises(ValueError):
        x[0] = 0.0
