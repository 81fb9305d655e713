"""Convection: fluid properties, textbook worked examples, mixed-convection limits."""

import numpy as np
import pytest
from scipy.integrate import quad

from shipthermal.environment import convection as cv
from shipthermal.errors import InputError


def test_air_properties_vs_incropera_table_a4():
    # Incropera et al., Table A.4 (air at 1 bar = 100 kPa): T, rho, mu*1e7, k*1e3, Pr.
    table = np.array([[250, 1.3947, 159.6, 22.3, 0.720],
                      [300, 1.1614, 184.6, 26.3, 0.707],
                      [350, 0.9950, 208.2, 30.0, 0.700],
                      [400, 0.8711, 230.1, 33.8, 0.690]])
    p = cv.air_properties(table[:, 0], pressure=1.0e5)
    # tolerance 1 %: Sutherland fits are quoted +-2 % (White) but match to ~0.6 % here;
    # the table carries 3-4 significant digits
    np.testing.assert_allclose(p.density, table[:, 1], rtol=1e-3)
    np.testing.assert_allclose(p.viscosity * 1e7, table[:, 2], rtol=1e-2)
    np.testing.assert_allclose(p.conductivity * 1e3, table[:, 3], rtol=1e-2)
    np.testing.assert_allclose(p.prandtl, table[:, 4], rtol=1e-2)


def test_water_properties_vs_iapws():
    # IAPWS 2008 viscosity of pure water at 0.1 MPa: 10 degC 1.3059e-3, 20 degC 1.0016e-3,
    # 30 degC 0.7972e-3 Pa s; IAPWS 2011 conductivity at 20 degC 0.5984 W/m/K.
    # Vogel's equation claims ~1 % over 10-30 degC; Ramires ~0.5 %.
    w = cv.seawater_properties(np.array([283.15, 293.15, 303.15]), salinity=0.0)
    np.testing.assert_allclose(w.viscosity, [1.3059e-3, 1.0016e-3, 0.7972e-3], rtol=1e-2)
    assert w.conductivity[1] == pytest.approx(0.5984, rel=5e-3)
    sw = cv.seawater_properties(293.15, salinity=0.035)
    # sea water is more viscous (Sharqawy et al. 2010: ~7-8 % at S = 35 g/kg)
    assert 1.05 < sw.viscosity / w.viscosity[1] < 1.10
    assert 6.5 < sw.prandtl < 8.0


def test_incropera_example_7_1_laminar_plate():
    # Incropera & DeWitt, 6th ed., Example 7.1: air at 300 degC and 6 kPa, 10 m/s over a
    # plate at 27 degC; properties at Tf = 437 K: nu = 5.21e-4 m2/s (at 6 kPa),
    # k = 0.0364 W/m/K, Pr = 0.687; first 0.5 m: Re = 9597, Nu = 57.4, h = 4.18 W/m2K,
    # q' = 570 W/m. Textbook rounding to 3 digits: rtol 2e-3.
    k, pr, nu = 0.0364, 0.687, 5.21e-4
    props = cv.FluidProperties(np.array(1.0), np.array(nu), np.array(k),
                               np.array(pr * k / nu), np.array(1 / 437.0))
    re = cv.reynolds(10.0, 0.5, props.kinematic_viscosity)
    assert re == pytest.approx(9597, rel=2e-3)
    assert cv.nusselt_forced_flat_plate(re, pr) == pytest.approx(57.4, rel=2e-3)
    h = cv.h_forced(10.0, 0.5, props)
    assert h == pytest.approx(4.18, rel=2e-3)
    assert h * 0.5 * (573.0 - 300.0) == pytest.approx(570.0, rel=3e-3)


def test_mixed_boundary_layer_equals_integral_of_local_correlations():
    # Average over the plate of the local laminar (0.332 Re_x^1/2 Pr^1/3) and turbulent
    # (0.0296 Re_x^0.8 Pr^1/3) Nusselt numbers (Incropera eqs. 7.23, 7.36) must equal
    # the closed form of eq. 7.38 (A = 871 for Re_c = 5e5).
    pr, rec = 0.71, 5.0e5
    for re in (1e6, 1e7, 1e8):
        xc = rec / re
        lam = quad(lambda x: 0.332 * (re * x) ** 0.5 / x, 0, xc)[0]
        tur = quad(lambda x: 0.0296 * (re * x) ** 0.8 / x, xc, 1)[0]
        expected = (lam + tur) * pr ** (1 / 3)
        assert cv.nusselt_forced_flat_plate(re, pr) == pytest.approx(expected, rel=1e-3)
    a = 0.037 * rec ** 0.8 - 0.664 * rec ** 0.5
    assert a == pytest.approx(871, abs=1)
    # continuous at the transition; tripped (turbulent) plate transfers more
    below, above = cv.nusselt_forced_flat_plate(np.array([rec * (1 - 1e-9), rec * (1 + 1e-9)]), pr)
    assert above == pytest.approx(below, rel=1e-6)
    assert cv.nusselt_forced_flat_plate(1e7, pr, "turbulent") > cv.nusselt_forced_flat_plate(1e7, pr)
    with pytest.raises(InputError, match="boundary_layer"):
        cv.nusselt_forced_flat_plate(1e6, pr, "transitional")


def test_incropera_example_9_2_vertical_plate():
    # Incropera & DeWitt, 6th ed., Example 9.2: glass fire screen 0.71 m high at 232 degC
    # in a 23 degC room; properties at Tf = 400 K: nu = 26.41e-6, k = 0.0338,
    # alpha = 38.3e-6, Pr = 0.690, beta = 1/400, g = 9.8: Ra = 1.813e9, Nu = 147,
    # h = 7.0 W/m2K. Textbook rounding: Ra, Nu to 3 digits, h to 2.
    k, a, nu = 0.0338, 38.3e-6, 26.41e-6
    props = cv.FluidProperties(np.array(1.0), np.array(nu), np.array(k),
                               np.array(k / a), np.array(1 / 400.0))
    ra = cv.rayleigh(505.15, 296.15, 0.71, props, gravity=9.8)
    assert ra == pytest.approx(1.813e9, rel=2e-3)
    nu_l = cv.nusselt_vertical_plate(ra, nu / a)
    assert nu_l == pytest.approx(147, rel=3e-3)
    assert nu_l * k / 0.71 == pytest.approx(7.0, rel=7e-3)
    # the tilt-aware function reduces to Churchill-Chu on a vertical face
    h = cv.h_natural(505.15, 296.15, 0.0, 0.71, 0.2, props)
    assert h == pytest.approx(nu_l * k / 0.71, rel=2e-3)  # g = 9.80665 vs 9.8


def test_horizontal_plate_branches_and_tilt_limits():
    ra = np.array([1e5, 1e8])
    up = cv.nusselt_horizontal_plate(ra, True)
    np.testing.assert_allclose(up, [0.54 * 1e5 ** 0.25, 0.15 * 1e8 ** (1 / 3)], rtol=1e-12)
    down = cv.nusselt_horizontal_plate(ra, False)
    np.testing.assert_allclose(down, 0.52 * ra ** 0.2, rtol=1e-12)
    assert np.all(down < up)
    # the two unstable branches meet where 0.54 Ra^1/4 = 0.15 Ra^1/3 (Ra = 4.8e6): Nu is
    # continuous, and within 6 % of the published switch at 1e7
    cross = (0.54 / 0.15) ** 12
    lo, hi = cv.nusselt_horizontal_plate(np.array([cross * (1 - 1e-9), cross * (1 + 1e-9)]),
                                         True)
    assert hi == pytest.approx(lo, rel=1e-9)
    at_switch = cv.nusselt_horizontal_plate(np.array([1e7 * (1 - 1e-12)]), True)[0]
    assert at_switch / (0.54 * 1e7 ** 0.25) - 1 == pytest.approx(0.0625, abs=0.002)
    props = cv.air_properties(310.0)
    # hot deck facing up (unstable) vs same plate facing down (stable)
    h_up = cv.h_natural(330.0, 290.0, 1.0, 3.0, 5.0, props)
    h_dn = cv.h_natural(330.0, 290.0, -1.0, 3.0, 5.0, props)
    ra_h = cv.rayleigh(330.0, 290.0, 5.0, props)
    assert h_up == pytest.approx(0.15 * ra_h ** (1 / 3) * props.conductivity / 5.0, rel=1e-12)
    # stable side, Ra = 2.8e10 (beyond 0.52 Ra^1/5's 1e9): Walton's floor, 1.810 dT^1/3 / 2.382
    assert ra_h > 1e10
    assert 0.52 * ra_h ** 0.2 * props.conductivity / 5.0 < 0.3 * h_dn
    assert h_dn == pytest.approx(1.810 * 40.0 ** (1 / 3) / 2.382, rel=1e-12)
    # a small plate at small Ra keeps the laminar stable correlation
    h_small = cv.h_natural(290.5, 290.0, -1.0, 0.1, 0.05, props)
    ra_s = cv.rayleigh(290.5, 290.0, 0.05, props)
    assert h_small == pytest.approx(0.52 * ra_s ** 0.2 * props.conductivity / 0.05, rel=1e-12)
    # a cold face looking down is unstable like a hot face looking up (symmetry in dT)
    assert cv.h_natural(250.0, 290.0, -1.0, 3.0, 5.0, props) == pytest.approx(
        cv.h_natural(330.0, 290.0, 1.0, 3.0, 5.0, props), rel=1e-12)
    # h of a tilted plate varies continuously between the limits
    nz = np.linspace(0, 1, 41)
    h = cv.h_natural(330.0, 290.0, nz, 3.0, 5.0, props)
    assert np.all(np.isfinite(h)) and np.all(h > 0)
    assert np.max(np.abs(np.diff(h))) < 0.2 * h.max()


def test_mixed_convection_limits():
    hf = np.array([0.0, 10.0, 10.0, 10.0, 0.0])
    hn = np.array([5.0, 0.0, 10.0, 10.0, 0.0])
    opp = np.array([False, False, False, True, False])
    h = cv.combine_mixed(hf, hn, opposing=opp)
    np.testing.assert_allclose(h, [5.0, 10.0, 10.0 * 2 ** (1 / 3), 0.0, 0.0], atol=1e-12)
    # assisting mixed convection is never below either mode nor above their sum
    rng = np.random.default_rng(1)
    a, b = rng.uniform(0, 20, 1000), rng.uniform(0, 20, 1000)
    m = cv.combine_mixed(a, b)
    assert np.all(m >= np.maximum(a, b) - 1e-12) and np.all(m <= a + b + 1e-12)
    # the cubes by products equal the power form; a scalar sign applies to all faces
    np.testing.assert_allclose(m, (a ** 3 + b ** 3) ** (1 / 3), rtol=1e-14)
    np.testing.assert_allclose(cv.combine_mixed(a, b, n=4.0), (a ** 4 + b ** 4) ** 0.25,
                               rtol=1e-14)
    np.testing.assert_array_equal(cv.combine_mixed(a, b, opposing=True),
                                  cv.combine_mixed(a, b, opposing=np.ones(1000, bool)))


def test_exterior_coefficient_tends_to_each_mode():
    ts, ta = 320.0, 300.0
    props = cv.air_properties(0.5 * (ts + ta))
    calm = cv.h_exterior_air(ts, ta, 1.0, 0.0, 50.0, 3.0, 5.0)
    assert calm == pytest.approx(cv.h_natural(ts, ta, 1.0, 3.0, 5.0, props), rel=1e-12)
    windy = cv.h_exterior_air(ts, ta, 1.0, 20.0, 50.0, 3.0, 5.0)
    hf = cv.h_forced(20.0, 50.0, props)
    assert 1.0 <= windy / hf < 1.02
    # more wind, more transfer
    h = cv.h_exterior_air(ts, ta, 0.0, np.linspace(0, 20, 21), 50.0, 3.0, 5.0)
    assert np.all(np.diff(h) > 0)


@pytest.mark.parametrize("heading, wind_dir, ship, wind, speed, frm, off_bow", [
    (0.0, 0.0, 10.0, 0.0, 10.0, 0.0, 0.0),       # calm: head wind from the ship's motion
    (0.0, 0.0, 10.0, 5.0, 15.0, 0.0, 0.0),       # head wind adds
    (0.0, 180.0, 10.0, 10.0, 0.0, None, None),   # following wind at ship speed: calm deck
    (90.0, 0.0, 0.0, 8.0, 8.0, 0.0, 270.0),      # moored heading east, north wind: port beam
    (90.0, 0.0, 5.0, 5.0, 5 * 2 ** 0.5, 45.0, 315.0),
])
def test_relative_wind(heading, wind_dir, ship, wind, speed, frm, off_bow):
    s, d, b = cv.relative_wind(wind, wind_dir, ship, heading)
    assert s == pytest.approx(speed, abs=1e-12)
    if frm is not None:
        assert d == pytest.approx(frm, abs=1e-9)
        assert b == pytest.approx(off_bow, abs=1e-9)


def test_hull_water_moored_and_under_way():
    ts, tw = 293.0, 290.0
    props = cv.seawater_properties(0.5 * (ts + tw))
    moored = cv.h_hull_water(ts, tw, 0.0, 100.0, 5.0)
    ra = cv.rayleigh(ts, tw, 5.0, props)
    nat = cv.nusselt_vertical_plate(ra, props.prandtl) * props.conductivity / 5.0
    assert moored == pytest.approx(nat, rel=1e-12)
    # moored natural convection in water: O(100) W/m2K for a few kelvin
    assert 50 < moored < 500
    # under way at 6 m/s on a 100 m hull: Re ~ 6e8, turbulent, h of order 1e4 W/m2K
    fast = cv.h_hull_water(ts, tw, 6.0, 100.0, 5.0)
    assert fast == pytest.approx(cv.combine_mixed(cv.h_forced(6.0, 100.0, props), nat), rel=1e-12)
    assert 3e3 < fast < 3e4
    assert cv.h_hull_water(ts, tw, 0.0, 100.0, 5.0, current_speed=0.5) > moored


def test_interior_iso6946():
    # ISO 6946:2017 Annex C: hci = 5.0 up, 2.5 horizontal, 0.7 down
    h = cv.h_interior_iso6946([295.0, 295.0, 295.0, 285.0], 290.0, [1.0, -1.0, 0.0, -1.0])
    np.testing.assert_allclose(h, [5.0, 0.7, 2.5, 5.0])
    # with radiation (eps 0.9, Tm 20 degC) the tabulated Rsi follow: 0.10, 0.13, 0.17 m2K/W
    # (the standard rounds to 2 digits: tolerance 0.005)
    tm = 293.15
    rsi = 1 / cv.h_interior_iso6946([tm + 1e-3, tm + 1e-3, tm + 1e-3], tm - 1e-3,
                                    [1.0, 0.0, -1.0], include_radiation=True)
    np.testing.assert_allclose(rsi, [0.10, 0.13, 0.17], atol=5e-3)
    nat = cv.h_interior(300.0, 290.0, 0.0, 2.5, 2.0, method="natural")
    assert 1.5 < nat < 4.0   # natural convection on a 2.5 m wall, 10 K
    with pytest.raises(InputError, match="interior.method"):
        cv.h_interior(300.0, 290.0, 0.0, method="cfd")


def test_wind_log_profile():
    assert cv.wind_speed_at_height(5.0, 10.0) == pytest.approx(5.0)
    # ln(20/2e-4) / ln(10/2e-4) = 11.5129 / 10.8198 = 1.06406
    assert cv.wind_speed_at_height(5.0, 20.0) == pytest.approx(5.0 * 1.06406, rel=1e-5)
    assert np.all(np.diff(cv.wind_speed_at_height(5.0, np.linspace(1, 40, 20))) > 0)


# ---- the exterior convection models ---------------------------------------------------------
def test_turbulent_model_is_incropera_7_41_blended_with_natural_convection():
    # Incropera 6th ed. eq. 7.41: Nu_L = 0.037 Re_L^0.8 Pr^1/3 (tripped at the leading edge),
    # blended with the natural coefficient by Churchill (1977), h³ = h_F³ + h_N³
    ts = np.array([300.0, 320.0, 280.0, 310.0])
    ta = np.array([295.0, 295.0, 290.0, 305.0])
    nz = np.array([0.0, 1.0, -1.0, 0.5])
    v = np.array([0.5, 3.0, 8.0, 15.0])
    length = np.array([2.0, 10.0, 40.0, 5.0])
    lv, lh = np.array([3.0, 3.0, 6.0, 2.0]), np.array([1.0, 2.5, 5.0, 1.2])
    props = cv.air_properties(0.5 * (ts + ta))
    re = v * length / props.kinematic_viscosity
    h_f = 0.037 * re ** 0.8 * props.prandtl ** (1 / 3) * props.conductivity / length
    h_n = cv.h_natural(ts, ta, nz, lv, lh, props)
    expected = (h_f ** 3 + h_n ** 3) ** (1 / 3)
    model = cv.CONVECTION_MODELS["flat_plate_turbulent"]
    flow = cv.ExteriorFlow(nz, v, length, lv, lh)
    np.testing.assert_allclose(model.h(ts, ta, flow), expected, rtol=1e-12)


def test_iso6946_exterior_model_is_four_plus_four_v():
    # ISO 6946:2017 Annex C eq. C.2; its design wind 4 m/s gives h_ce = 20 W m-2 K-1
    v = np.array([0.0, 1.0, 4.0, 10.0])
    model = cv.CONVECTION_MODELS["iso6946"]
    h = model.h(np.full(4, 300.0), 290.0, cv.ExteriorFlow(0.0, v, 10.0, 3.0, 1.0))
    np.testing.assert_array_equal(h, [4.0, 8.0, 20.0, 44.0])


def test_unknown_names_are_listed():
    assert cv.convection_model(cv.CONVECTION_MODELS["iso6946"]).name == "iso6946"
    with pytest.raises(InputError) as err:
        cv.convection_model("jurges")
    assert err.value.field == "convection.model"
    assert all(name in err.value.allowed for name in cv.CONVECTION_MODELS)
    for model in cv.CONVECTION_MODELS.values():
        assert model.source and model.validity
