"""The exterior convection models: each one's law of the surface temperature (what the
solver evaluates at the solved surface temperature) against its own correlation functions,
the published equations by hand, the slope the solver's Jacobian takes, and the stable-side
floor at ship scale."""

import numpy as np
import pytest

from shipthermal.conditions import ConvectionLaw, law_h
from shipthermal.environment import convection as cv
from shipthermal.errors import InputError

RNG = np.random.default_rng(7)
N = 4000


def _flows():
    """Random faces and winds over the ranges a ship sees (some calm, some vertical)."""
    nz = RNG.choice([0.0, 1.0, -1.0, 0.3, -0.7, 0.99], N)
    v = np.where(RNG.random(N) < 0.1, 0.0, RNG.uniform(0.0, 15.0, N))
    flow = cv.ExteriorFlow(normal_z=nz, wind_speed=v, length_flow=RNG.uniform(1, 150, N),
                           length_vertical=RNG.uniform(0.5, 20, N),
                           length_horizontal=RNG.uniform(0.3, 30, N),
                           windward=RNG.random(N) < 0.5,
                           perimeter_over_area=RNG.uniform(0.02, 3.0, N),
                           roughness=RNG.choice(list(cv.ROUGHNESS_MULTIPLIERS.values()), N))
    ta = RNG.uniform(260.0, 310.0, N)
    ts = ta + np.where(RNG.random(N) < 0.05, 0.0, RNG.uniform(-25.0, 40.0, N))
    return flow, ts, ta


@pytest.mark.parametrize("name", list(cv.CONVECTION_MODELS))
def test_each_models_law_is_its_correlation(name):
    # the solver's form (forced part + law, conditions.law_h) against the correlation
    # functions of the module, which compute the same physics without the law arrays
    model = cv.CONVECTION_MODELS[name]
    flow, ts, ta = _flows()
    np.testing.assert_allclose(model.h(ts, ta, flow), model.h_direct(ts, ta, flow),
                               rtol=2e-13, atol=1e-13)
    assert model.source and model.validity


@pytest.mark.parametrize("name", list(cv.CONVECTION_MODELS))
def test_the_natural_law_alone_is_the_laws_natural_part(name):
    # the solver's steps ask for the natural part alone (no forced part computed)
    model = cv.CONVECTION_MODELS[name]
    flow, ts, ta = _flows()
    film = 0.5 * (ts + ta)
    assert np.array_equal(model.natural_law(film, flow), model.terms(film, flow)[1].natural)
    assert (model.natural is not None) == model.film_dependent


@pytest.mark.parametrize("name", list(cv.CONVECTION_MODELS))
def test_law_slope_is_the_derivative_and_the_flux_increases(name):
    model = cv.CONVECTION_MODELS[name]
    flow, ts, ta = _flows()
    hf, law = model.terms(0.5 * (ts + ta), flow)
    d = ts - ta
    h, slope = law_h(hf, law, d, return_slope=True)
    # x ∂h/∂x against central differences (faces away from dT = 0, where h has a kink)
    far = np.abs(d) > 0.05
    eps = 1e-6 * np.maximum(np.abs(d), 1.0)
    dh = (law_h(hf, law, d + eps) - law_h(hf, law, d - eps)) / (2 * eps)
    np.testing.assert_allclose(slope[far], (d * dh)[far], rtol=1e-5, atol=1e-8)
    # the convective flux h dT never decreases with the surface temperature (the face
    # balance stays strictly decreasing: one root); it is flat only at dT = 0 in calm air
    assert np.all(h + slope >= 0.0)
    assert np.all((h + slope > 0.0) | ((d == 0.0) & (np.asarray(flow.wind_speed) == 0.0)))


def test_walton_natural_convection_by_hand():
    # EnergyPlus Engineering Reference, TARP: 9.482 |dT|^1/3 / (7.238 - |cos S|) unstable,
    # 1.810 |dT|^1/3 / (1.382 + |cos S|) stable, 1.31 |dT|^1/3 vertical; dT = 8 K (cube root 2)
    h = cv.h_natural_walton(np.array([308.0, 292.0, 308.0, 308.0]), 300.0,
                            np.array([1.0, 1.0, -1.0, 0.0]))
    np.testing.assert_allclose(h, [2 * 9.482 / 6.238, 2 * 1.810 / 2.382, 2 * 1.810 / 2.382,
                                   2 * 1.31], rtol=1e-14)


def test_doe2_tarp_mowitt_mcadams_by_hand():
    # a hot roof (dT = +8 K, cube root 2), 3 m/s, concrete-like roughness R_f = 1.52
    hn = 2 * 9.482 / 6.238
    hf = 3.26 * 3.0 ** 0.89
    glass = np.hypot(hn, hf)
    assert cv.h_exterior_doe2(308.0, 300.0, 1.0, 3.0, True, 1.52) == pytest.approx(
        hn + 1.52 * (glass - hn), rel=1e-14)
    # a leeward wall: MoWiTT's leeward coefficients, and TARP's W_f = 0.5
    hl = 3.55 * 3.0 ** 0.617
    assert cv.h_exterior_mowitt(308.0, 300.0, 3.0, False) == pytest.approx(
        np.hypot(0.84 * 2, hl), rel=1e-14)
    assert cv.h_exterior_tarp(308.0, 300.0, 0.0, 3.0, 0.5, False, 1.11) == pytest.approx(
        2 * 1.31 + 2.537 * 0.5 * 1.11 * np.sqrt(0.5 * 3.0), rel=1e-14)
    assert cv.CONVECTION_MODELS["mcadams"].h(308.0, 300.0, cv.ExteriorFlow(1.0, 3.0)) == \
        pytest.approx(5.7 + 3.8 * 3.0, rel=1e-14)


def test_windward_is_within_ninety_degrees_or_horizontal():
    normals = np.array([[1.0, 0, 0], [-1.0, 0, 0], [0, 1.0, 0], [0, 0, 1.0], [0.1, 0, -0.995]])
    wind_from = np.array([1.0, 0.0])
    np.testing.assert_array_equal(cv.is_windward(normals, wind_from),
                                  [True, False, True, True, True])


def test_stable_side_floor_at_ship_scale():
    # a calm clear night: a 20 m deck 5 K below the air. The laminar stable correlation
    # (0.52 Ra^1/5, stated up to Ra 1e9) would give h ~ 0.3 at Ra ~ 1e11; the floor is
    # Walton's, 1.810 * 5^1/3 / 2.382 = 1.30 W m-2 K-1 (MoWiTT's calm-air 0.84 * 5^1/3 = 1.44)
    model = cv.CONVECTION_MODELS["flat_plate_mixed"]
    flow = cv.ExteriorFlow(1.0, 0.0, 20.0, 1.0, 5.0)
    h = float(model.h(283.0, 288.0, flow))
    props = cv.air_properties(285.5)
    ra = cv.rayleigh(283.0, 288.0, 5.0, props)
    assert ra > 1e10
    laminar = 0.52 * ra ** 0.2 * props.conductivity / 5.0
    assert laminar < 0.45
    assert h == pytest.approx(1.810 * 5.0 ** (1 / 3) / 2.382, rel=1e-12)


def test_law_sides_follow_the_buoyancy():
    # hot face up and cold face down are the unstable side; a vertical face has one law
    nat = np.zeros((2, 6))
    nat[0, 0], nat[1, 0] = 2.0, 1.0
    nat[:, 1] = 1.0 / 3.0
    for nz, d, want in ((1.0, 8.0, 4.0), (1.0, -8.0, 2.0), (-1.0, -8.0, 4.0), (-1.0, 8.0, 2.0),
                        (0.0, 8.0, 4.0), (0.0, -8.0, 4.0)):
        assert law_h(0.0, ConvectionLaw(nat, 1.0, 1.0, nz), d) == pytest.approx(want)


def test_unknown_names_list_the_known_ones():
    with pytest.raises(InputError) as err:
        cv.roughness_multiplier("sandpaper", "convection.roughness.deck")
    assert err.value.field == "convection.roughness.deck"
    assert all(k in err.value.allowed for k in cv.ROUGHNESS_MULTIPLIERS)
    with pytest.raises(InputError) as err:
        cv.convection_model("blocken", "convection.model.deck")
    assert err.value.field == "convection.model.deck"
    assert all(k in err.value.allowed for k in cv.CONVECTION_MODELS)
