"""Real and user sensors: named bands, presets, products (radiance, brightness temperature,
digital numbers), bad response tables."""

import numpy as np
import pytest

from imaging import instruments as ins
from imaging.radiometry import band_radiance, band_radiance_dt
from shipthermal.optics.responses import (BAND_NAMES, named_band, nominal_range, read_response_file,
                                    response_from_table)
from shipthermal.errors import InputError


def test_paper_instrument_is_the_default_preset():
    p = ins.instrument("paper")
    assert ins.PRESET_NAMES[0] == "paper"
    assert p.nadir_gsd_m == pytest.approx(30.0, rel=1e-3)
    assert p.band_keys == ("3-5", "8-14")
    assert all(b.netd_K is None for b in p.bands)


@pytest.mark.parametrize("name, gsd", [("landsat8_tirs", 99.0), ("landsat9_tirs2", 99.0),
                                       ("sdgsat1_tis", 30.0), ("ecostress", 70.0)])
def test_preset_ground_sample_distance(name, gsd):
    assert ins.instrument(name).nadir_gsd_m == pytest.approx(gsd, rel=2e-3)


def test_landsat8_band10_response_is_the_usgs_table():
    r = named_band("landsat8_tirs_b10")
    assert r.wavelength_um[0] == 9.0 and r.wavelength_um[-1] == 14.0 and r.response.max() == 1.0
    lo, hi = nominal_range(r)
    assert lo == pytest.approx(10.60, abs=0.01) and hi == pytest.approx(11.19, abs=0.02)


# Landsat-8 band 10 with the measured response: K1/K2 (a fit USGS made to the response)
# vs the exact band Planck integral. Measured: +0.118 K at 300 K, max 0.139 K over
# 240-340 K; band 11 (rectangle at the edges, not the real response): max 0.142 K.
@pytest.mark.parametrize("band, tol", [("landsat8_tirs_b10", 0.15), ("landsat8_tirs_b11", 0.15),
                                       ("landsat9_tirs2_b10", 0.35),
                                       ("landsat9_tirs2_b11", 0.40)])
def test_k1k2_brightness_temperature_against_the_response_table(band, tol):
    preset = "landsat8_tirs" if band.startswith("landsat8") else "landsat9_tirs2"
    b = ins.instrument(preset).band(band)
    d = ins.k1k2_difference(b, (240.0, 340.0))
    assert d["max_abs_K"] < tol, d


@pytest.mark.parametrize("preset", ["sdgsat1_tis", "ecostress", "paper"])
def test_brightness_temperature_inverts_the_band_radiance(preset):
    for b in ins.instrument(preset).bands:
        t = np.array([240.0, 290.0, 340.0])
        got = ins.product_brightness_temperature(band_radiance(t, b.response), b)
        np.testing.assert_allclose(got, t, atol=1e-6)


def test_digital_numbers_round_trip_within_half_a_step():
    b = ins.instrument("landsat8_tirs").band("landsat8_tirs_b10")
    lr = band_radiance(np.linspace(250.0, 330.0, 50), b.response)
    back = ins.from_dn(ins.to_dn(lr, b), b)
    step = 3.342e-4 * b.width_um   # Landsat's RADIANCE_MULT in band radiance
    assert np.max(np.abs(back - lr)) <= 0.5 * step + 1e-12
    # the rescaling is Landsat's: L = 3.342e-4 Q + 0.1 (band-mean spectral radiance)
    q = ins.to_dn(lr[:1], b)[0]
    assert ins.band_mean_radiance(lr[0], b) == pytest.approx(3.342e-4 * q + 0.1, abs=2e-4)


def test_noise_is_netd_times_the_responsivity():
    b = ins.instrument("sdgsat1_tis").bands[1]
    assert ins.noise_sigma(b, 0.8) == pytest.approx(0.2 * 0.8 * band_radiance_dt(
        300.0, b.response))


def test_every_named_band_lies_inside_the_tables():
    for name in BAND_NAMES:
        r = named_band(name)
        assert r.wavelength_um[0] >= 2.9 and r.wavelength_um[-1] <= 14.5


@pytest.mark.parametrize("rows, key, words", [
    ([(-1.0, 0.0), (10.0, 1.0)], "wavelength_um", "positive"),
    ([(10.0, 0.5), (9.0, 1.0), (11.0, 0.2)], "wavelength_um", "increase"),
    ([(10.0, 0.5), (10.0, 1.0)], "wavelength_um", "increase"),
    ([(10.0, -0.1), (11.0, 1.0)], "relative_response", "negative"),
    ([(15.0, 1.0), (16.0, 1.0)], "wavelength_um", "2.9-14.5"),
])
def test_bad_response_table_is_refused_with_the_fix(rows, key, words):
    wl, r = zip(*rows)
    with pytest.raises(InputError) as exc:
        response_from_table("mine", wl, r)
    assert key in exc.value.field and words in str(exc.value)


def test_response_file_reader(tmp_path):
    f = tmp_path / "band.csv"
    f.write_text("# my band\nwavelength_um,response\n10.0,0\n10.5,1\n11.0,0.5\n11.5,0\n")
    r = read_response_file(f)
    assert r.name == "band" and r.response.max() == 1.0 and r.wavelength_um.size == 4
    bad = tmp_path / "bad.txt"
    bad.write_text("10.0 0\n9.5 1\n")
    with pytest.raises(InputError, match="increase"):
        read_response_file(bad)
    with pytest.raises(InputError, match="existing file"):
        read_response_file(tmp_path / "nope.csv")


def test_unknown_preset_lists_the_allowed():
    with pytest.raises(InputError) as exc:
        ins.instrument("landsat7")
    assert all(p in str(exc.value) for p in ins.PRESET_NAMES)


def test_psf_of_a_detector_coarser_than_the_product_grid():
    """Landsat TIRS: 99 m detector footprint on the 30 m product grid. The blur (diffraction
    and the detector box in detector units) keeps the mean and spreads a point over about
    the footprint: its second moment grows with the detector box's 1/12 pitch² (~ 0.82 pixels
    of the grid per axis for a 3.3-pixel box)."""
    from imaging.sensor import apply_psf

    inst = ins.instrument("landsat8_tirs")
    img = np.zeros((65, 65))
    img[32, 32] = 1.0
    ratio = inst.nadir_gsd_m / 30.0
    out = apply_psf(img, 10.9, inst.spec, samples_per_pixel=ratio, include_detector=True)
    # the Airy wings beyond the 65-pixel window carry ~1 % (they fall as r^-3)
    assert 0.98 < out.sum() < 1.0
    flat = apply_psf(np.full((40, 40), 7.0), 10.9, inst.spec, samples_per_pixel=ratio,
                     include_detector=True)
    np.testing.assert_allclose(flat, 7.0, rtol=1e-9)
    y, x = np.mgrid[:65, :65]
    var = float((out * (x - 32) ** 2).sum())
    assert var > ratio ** 2 / 12.0                       # at least the box's own variance
    plain = apply_psf(img, 10.9, inst.spec)              # detector = grid pixel: far narrower
    assert float((plain * (x - 32) ** 2).sum()) < 0.5 * var
