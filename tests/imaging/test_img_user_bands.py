"""A user's spectral response: its atmosphere on the day's state (the spectral bins), and
its name in the imaging run (``shipthermal.optics.responses.user_bands``).

Peer: live LOWTRAN 7 (Navy maritime aerosol, 23 km) at random days, stored by
``scripts/make_atmosphere_tables.py --bins`` in ``data/user_band_lowtran.json`` (the
responses are shapes no named band has: a triangle over 10-12.5 µm, rectangles over the
3.7-4.1 µm window and 8.2-9.2 µm, a Gaussian on the 4.6 µm CO band wing).
"""

import json
from pathlib import Path

import numpy as np
import pytest

from imaging.atmosphere import MODEL_NAMES, AtmosphereState, atmosphere, surface_state
from imaging.atmosphere import spectral_bins as sb
from shipthermal.optics.responses import (named_band, response_from_table, user_band_names,
                                    user_bands)
from shipthermal.errors import InputError

REFERENCE = json.loads((Path(__file__).parent / "data" / "user_band_lowtran.json")
                       .read_text(encoding="utf-8"))

#: Largest relative error allowed against live LOWTRAN per quantity: the 1 % the
#: atmosphere is held to against LOWTRAN (issue's target for the named bands); the direct
#: sun 1.5 %, the named bands' own stated state error for it (1.4 %, ``interpolation_errors``)
#: rounded up — a bin carries the state with the same interpolation over the same nodes.
TOLERANCE = {"transmittance": 0.01, "path_radiance": 0.01, "sky_radiance": 0.01,
             "solar_irradiance": 0.015}


def _response(label):
    r = REFERENCE["responses"][label]
    return response_from_table(label, r["wavelength_um"], r["response"])


def _cases(model, cloudy=False):
    return [c for c in REFERENCE["cases"]
            if c["model"] == model and ("cloud_type" in c) == cloudy]


@pytest.mark.parametrize("model", MODEL_NAMES)
def test_user_response_on_the_days_state_against_live_lowtran(model):
    worst = {q: 0.0 for q in TOLERANCE}
    for c in _cases(model):
        s0 = surface_state(model)
        st = AtmosphereState(temp_air_K=s0.temp_air_K + c["temp_offset_K"],
                             rel_humidity=c["rel_humidity"], wind_speed=c["wind_speed"])
        r = atmosphere(model, _response(c["response"]), c["view_zenith_deg"],
                       c["sun_zenith_deg"], sky_zenith_deg=c["sky_zenith_deg"], state=st,
                       spectral=False)
        got = {"transmittance": r.transmittance, "path_radiance": r.path_radiance_thermal,
               "sky_radiance": r.sky_radiance, "solar_irradiance": r.solar_irradiance_ground}
        for q, live in c["live"].items():
            if live > 0:
                worst[q] = max(worst[q], abs(got[q] / live - 1.0))
    assert len(_cases(model)) >= 32
    for q, tol in TOLERANCE.items():
        assert worst[q] <= tol, (q, worst[q])


@pytest.mark.parametrize("model", MODEL_NAMES)
def test_user_response_under_lowtrans_cloud_decks(model):
    """Overcast (cloud cover 1) under each of LOWTRAN's five decks on a random day, zenith 0
    and 60°: within the 2 % the overcast sky is held to against the decks. (Before the bins
    held the decks, a user band took its nearest named band's cloudy/clear ratio: up to 70 %
    off in a window, where the clear sky is dark and the cloud base is not.)"""
    from imaging.atmosphere import sky_radiance

    worst = 0.0
    for c in _cases(model, cloudy=True):
        s0 = surface_state(model)
        st = AtmosphereState(temp_air_K=s0.temp_air_K + c["temp_offset_K"],
                             rel_humidity=c["rel_humidity"])
        got = float(sky_radiance(model, _response(c["response"]), c["sky_zenith_deg"],
                                 state=st, cloud_cover=1.0, cloud_type=c["cloud_type"]))
        worst = max(worst, abs(got / c["live"]["sky_radiance_cloudy"] - 1.0))
    assert len(_cases(model, cloudy=True)) == 4 * 5 * 2
    assert worst <= 0.02, worst


@pytest.mark.parametrize("model", ["tropical", "subarctic_winter"])
def test_user_response_at_the_models_own_state_is_its_spectra(model):
    """At the model's own state every bin factor is 1: the value is the response's integral
    of the stored own-state spectra at that zenith (table nodes: between them the band value
    and the spectrum are each interpolated, which PCHIP does not commute with)."""
    from imaging.atmosphere import band_integrate

    resp = _response("rect_3.7-4.1um")
    for vz in (0.0, 30.0, 70.0):
        r = atmosphere(model, resp, vz, 120.0, spectral=True)
        lam = r.wavelength_um
        tau = band_integrate(lam, r.transmittance_spectral, None, response=resp, mean=True)
        path = band_integrate(lam, r.path_radiance_spectral, None, response=resp)
        assert r.transmittance == pytest.approx(tau, rel=1e-6)
        assert r.path_radiance_thermal == pytest.approx(path, rel=1e-6)


def test_bins_cover_the_tables_wavelengths():
    from imaging.atmosphere import load_table

    k = sb.bin_index(load_table().wavelength_um)
    assert np.all(k >= 0)                                   # every sample has a bin
    assert np.all(np.bincount(k) >= 2)                      # and no bin is empty or single


def test_a_copy_of_a_named_band_is_looked_up_as_that_band():
    """A user's copy of Landsat-8 band 10 (its measured table) takes the band's own tables:
    the same numbers on any day."""
    resp = named_band("landsat8_tirs_b10")
    user = response_from_table("l8_user", resp.wavelength_um, resp.response)
    st = AtmosphereState(temp_air_K=300.0, rel_humidity=82.0, wind_speed=8.0)
    a = atmosphere("midlatitude_summer", user, 20.0, 40.0, state=st, spectral=False)
    b = atmosphere("midlatitude_summer", "landsat8_tirs_b10", 20.0, 40.0, state=st,
                   spectral=False)
    for f in ("transmittance", "path_radiance_thermal", "sky_radiance", "solar_irradiance_ground"):
        assert getattr(a, f) == getattr(b, f), f


def test_the_bins_agree_with_the_band_tables_for_a_slightly_different_response():
    """Band 10 with one knot's response changed by 2 % is not a named band: it goes through
    the spectral bins, whose values on a scaled day must agree with band 10's own tables
    within the two methods' stated state errors (≤ 1.7 % path and sky for band 10)."""
    resp = named_band("landsat8_tirs_b10")
    r = resp.response.copy()
    r[len(r) // 3] *= 0.98
    user = response_from_table("l8_user", resp.wavelength_um, r)
    for model in ("midlatitude_summer", "subarctic_winter"):
        s0 = surface_state(model)
        st = AtmosphereState(temp_air_K=s0.temp_air_K + 6.0, rel_humidity=82.0, wind_speed=3.0)
        a = atmosphere(model, user, 20.0, 40.0, state=st, spectral=False)
        b = atmosphere(model, "landsat8_tirs_b10", 20.0, 40.0, state=st, spectral=False)
        assert a.transmittance == pytest.approx(b.transmittance, rel=0.005)
        for f in ("path_radiance_thermal", "sky_radiance"):
            assert getattr(a, f) == pytest.approx(getattr(b, f), rel=0.017), (model, f)


# ---------------------------------------------------------------- user band names
def test_user_bands_are_named_inside_the_block_only():
    resp = response_from_table("user", [10.0, 11.0, 12.0], [0.0, 1.0, 0.0])
    with user_bands([resp]):
        assert "user" in user_band_names()
        assert named_band("user") is resp
        r = atmosphere("tropical", "user", 0.0, 120.0, spectral=False)
        assert r.transmittance == pytest.approx(
            atmosphere("tropical", resp, 0.0, 120.0, spectral=False).transmittance)
    assert "user" not in user_band_names()
    with pytest.raises(InputError):
        named_band("user")


def test_a_user_band_may_not_shadow_a_named_band_or_change_inside_a_block():
    with pytest.raises(InputError, match="another name"):
        with user_bands([response_from_table("8-14", [8.0, 14.0], [1.0, 1.0])]):
            pass
    a = response_from_table("user", [10.0, 12.0], [1.0, 1.0])
    b = response_from_table("user", [3.5, 4.0], [1.0, 1.0])
    with user_bands([a]):
        with user_bands([a]):                   # the same sensor twice: fine
            pass
        with pytest.raises(InputError, match="different names"):
            with user_bands([b]):
                pass
        assert named_band("user") is a
    assert "user" not in user_band_names()


# ---------------------------------------------------------------- the imaging run
def test_a_user_band_equal_to_the_papers_renders_the_same_frames():
    """The 8-14 µm rectangle as a user's band ("user") renders the paper's 8-14 µm frames:
    same atmosphere (a copy of a named band takes its tables), emissivities (the band's
    half-maximum range), sea optics and metrics; the name is known for the run only."""
    from imaging.experiment import ImagingScenario, render_series
    from imaging.scene import GriddedBackground, ShipPlacement
    from imaging.thermal_history import ShipThermalHistory
    from shipthermal.raytrace.scenes import box

    V, F = box([-10.0, -3.0, -1.0], [10.0, 3.0, 4.0])
    times = np.array([0.0, 86400.0])
    h = ShipThermalHistory(V, F, np.zeros(len(F), int), ("deck",), times,
                           np.array([[288.0] * len(F), [300.0] * len(F)]))
    cm = np.ones((30, 30), np.uint8)
    cm[:, :5] = 3
    bg = GriddedBackground(cm, np.arange(24.0), np.broadcast_to(
        289.0 + 0.2 * (np.indices((30, 30)).sum(axis=0) % 2), (24, 30, 30)).copy(), 30.0)
    user = response_from_table("user", [8.0, 14.0], [1.0, 1.0])
    common = dict(background=bg, wind_speed=4.0, placement=ShipPlacement(450.0, 450.0, 30.0),
                  samples_per_pixel=16, date="2023-07-15", latitude=38.91, longitude=121.63,
                  tz="Etc/GMT-8")
    t = np.array([6.0, 12.0, 22.0]) * 3600.0
    paper = render_series(h, ImagingScenario("summer", **common), ("8-14",), t,
                          keep_times_s=t, progress=False)["8-14"]
    mine = render_series(h, ImagingScenario("summer", user_bands=(user,), **common), ("user",),
                         t, keep_times_s=t, progress=False)["user"]
    for k in t:
        np.testing.assert_array_equal(mine.frames[float(k)].radiance,
                                      paper.frames[float(k)].radiance)
    np.testing.assert_allclose(mine.metrics["contrast"], paper.metrics["contrast"], rtol=0,
                               atol=0)
    assert "user" not in user_band_names()
