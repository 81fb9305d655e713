"""Tests for imaging.sensor: geometry, camera equation, mixing, PSF, noise, quantisation."""

import math

import numpy as np
import pytest

from imaging import sensor as S
from imaging.radiometry import band_radiance, band_radiance_dt, standard_band
from imaging.scene import enu_direction
from shipthermal.errors import InputError


def test_nadir_gsd_is_30_m():
    # 795e3 * 40e-6 / 1.06 = 30.0 exactly in decimal; 1 ulp-level in binary
    assert S.PAPER_SENSOR.nadir_gsd_m == pytest.approx(30.0, abs=1e-12)
    along, across = S.ground_sample_distance()
    assert along == pytest.approx(30.0, abs=1e-9) and across == pytest.approx(30.0, abs=1e-9)
    assert S.PAPER_SENSOR.f_number == pytest.approx(2.0, abs=1e-15)


def test_off_nadir_gsd_flat_earth_closed_form():
    th = math.radians(30.0)
    along, across = S.ground_sample_distance(view_zenith=30.0, earth_radius_m=None)
    assert across == pytest.approx(30.0 / math.cos(th), rel=1e-14)
    assert along == pytest.approx(30.0 / math.cos(th) ** 2, rel=1e-14)


def test_off_nadir_gsd_sphere_against_finite_difference_of_ground_arc():
    # spherical Earth: ground position as a function of the look angle alpha at the
    # satellite; GSD along = ds/dalpha * (p / f), checked by central differences
    re, h = S.EARTH_RADIUS_M, S.PAPER_SENSOR.altitude_m
    th = math.radians(40.0)
    alpha = math.asin(re * math.sin(th) / (re + h))

    def arc(a):
        # Earth-centre angle gamma = asin((re+h) sin a / re) - a (incidence minus look)
        return re * (math.asin((re + h) * math.sin(a) / re) - a)

    da = 1e-7
    ds_dalpha = (arc(alpha + da) - arc(alpha - da)) / (2 * da)
    along, across = S.ground_sample_distance(view_zenith=40.0)
    ifov = S.PAPER_SENSOR.pixel_pitch_m / S.PAPER_SENSOR.focal_length_m
    assert along == pytest.approx(ds_dalpha * ifov, rel=1e-7)   # FD error ~ da^2
    # across: slant range times the IFOV; range from the law of cosines
    gamma = arc(alpha) / re
    rng = math.sqrt(re**2 + (re + h) ** 2 - 2 * re * (re + h) * math.cos(gamma))
    assert across == pytest.approx(rng * ifov, rel=1e-12)


def test_enu_direction_convention_matches_sun_azimuth():
    # azimuth clockwise from north: 90 deg = east
    v = enu_direction(30.0, 90.0)
    assert np.allclose(v, [0.5, 0.0, math.cos(math.radians(30.0))], atol=1e-15)


def test_camera_equation_values():
    lum = 10.0
    e = S.focal_plane_irradiance(lum)
    # tau pi L / (4 N^2) with N = 2: 0.7 * pi * 10 / 16
    assert e == pytest.approx(0.7 * math.pi * 10 / 16, rel=1e-14)
    e_thin = S.focal_plane_irradiance(lum, model="thin_lens")
    assert e_thin == pytest.approx(0.7 * math.pi * 10 / 17, rel=1e-14)
    assert S.focal_plane_irradiance(lum, field_angle=5.0) == pytest.approx(
        e * math.cos(math.radians(5.0)) ** 4, rel=1e-14)


def test_camera_equation_by_etendue():
    # independent route: power through the pupil from one pixel's footprint,
    # P = tau L A_pupil Omega_pixel, Omega = (p/f)^2; E = P / p^2 = tau L pi D^2 / (4 f^2)
    spec = S.PAPER_SENSOR
    lum = 3.7
    power = (spec.optics_transmittance * lum * math.pi * spec.aperture_m**2 / 4
             * (spec.pixel_pitch_m / spec.focal_length_m) ** 2)
    assert S.focal_plane_irradiance(lum) * spec.pixel_pitch_m**2 == pytest.approx(power,
                                                                                  rel=1e-13)


def test_at_aperture_radiance_eq1():
    assert S.at_aperture_radiance(np.array([5.0, 7.0]), 0.8, 1.5) == pytest.approx([5.5, 7.1])


def test_half_pixel_target_gives_half_mixed_radiance():
    lt, lb = 9.3, 4.1
    assert S.mix_subpixel(0.5, lt, lb) == pytest.approx(0.5 * (lt + lb), rel=1e-15)
    assert S.mix_subpixel(0.0, lt, lb) == lb and S.mix_subpixel(1.0, lt, lb) == lt
    with pytest.raises(InputError, match="coverage_fraction"):
        S.mix_subpixel(1.2, lt, lb)


def test_supersampled_half_plane_ship_mixes_by_area():
    # a 16 x 16 sampled render: target occupies the left half of pixel (1, 1) and all of
    # pixel (1, 2); the block mean must give coverage 0.5 / 1 and the mixed radiances
    s, lt, lb = 16, 9.3, 4.1
    mask = np.zeros((3 * s, 4 * s), dtype=bool)
    mask[s:2 * s, s:s + s // 2] = True
    mask[s:2 * s, 2 * s:3 * s] = True
    render = np.where(mask, lt, lb)
    cov = S.pixel_average(mask, s)
    img = S.pixel_average(render, s)
    assert cov[1, 1] == 0.5 and cov[1, 2] == 1.0 and cov[0, 0] == 0.0
    assert np.allclose(img, S.mix_subpixel(cov, lt, lb), rtol=1e-15)
    assert img[1, 1] == pytest.approx(0.5 * (lt + lb), rel=1e-15)


def test_pixel_average_rejects_ragged_shape():
    with pytest.raises(InputError, match="multiples"):
        S.pixel_average(np.zeros((17, 16)), 16)


def test_diffraction_mtf_closed_form_point():
    # at half the cut-off: (2/pi)(acos 0.5 - 0.5 sqrt(0.75)) = 0.391002...
    spec = S.PAPER_SENSOR
    lam = 11.0
    nu_c = spec.pixel_pitch_m / (lam * 1e-6 * spec.f_number)
    otf = S.optical_transfer_function(0.5 * nu_c, 0.0, lam, include_detector=False)
    assert otf == pytest.approx((2 / math.pi) * (math.acos(0.5) - 0.5 * math.sqrt(0.75)),
                                rel=1e-14)
    assert S.optical_transfer_function(1.01 * nu_c, 0.0, lam, include_detector=False) == 0.0
    # detector sinc at Nyquist: 2/pi
    assert S.optical_transfer_function(0.5, 0.0, 1e-6, include_detector=True) == pytest.approx(
        (2 / math.pi) * S.optical_transfer_function(0.5, 0.0, 1e-6, include_detector=False))


@pytest.mark.parametrize("band", ["3-5", "8-14"])
def test_fft_psf_matches_direct_airy_pixel_quadrature(band):
    # FFT route (OTF on a 15x supersampled grid, then the pixel block mean) vs the Airy
    # pattern integrated over pixels in real space: two independent computations
    lam = standard_band(band).mean_wavelength_um
    s, n = 15, 17
    img = np.zeros((n * s, n * s))
    img[n * s // 2, n * s // 2] = s * s          # unit energy in pixel units
    fft_kernel = S.pixel_average(S.apply_psf(img, lam, samples_per_pixel=s), s)
    direct = S.psf_kernel(lam, half_width=n // 2, oversample=s)
    # measured 1.9e-6 (4 um) and 5.2e-6 (11 um): midpoint-rule error of the direct sum
    assert np.max(np.abs(fft_kernel - direct)) < 2e-5
    # ensquared energy of the centre pixel: > 80 % (the Airy core is < 1 pixel here)
    assert direct[n // 2, n // 2] > 0.8


def test_apply_psf_preserves_mean_and_constant_images():
    rng = np.random.default_rng(3)
    img = rng.normal(5.0, 1.0, (64, 80))
    out = S.apply_psf(img, 11.0)
    assert np.allclose(S.apply_psf(np.full((32, 32), 2.5), 11.0), 2.5, rtol=1e-13)
    # reflect padding makes the mean conserved only approximately at the borders
    assert out.mean() == pytest.approx(img.mean(), rel=2e-3)
    assert out.std() < img.std()


def test_netd_noise_statistics_and_seed():
    dl_dt = float(band_radiance_dt(300.0, "8-14"))
    clean = np.full((400, 400), float(band_radiance(300.0, "8-14")))
    a = S.add_netd_noise(clean, 0.05, dl_dt, seed=7)
    b = S.add_netd_noise(clean, 0.05, dl_dt, seed=7)
    assert np.array_equal(a, b)
    # std estimate from 160 000 samples: relative standard error 1/sqrt(2n) = 0.18 %
    assert (a - clean).std() == pytest.approx(0.05 * dl_dt, rel=0.01)
    assert abs((a - clean).mean()) < 5 * 0.05 * dl_dt / 400


def test_quantisation_error_bounded_by_half_step():
    rng = np.random.default_rng(5)
    x = rng.uniform(0.0, 10.0, 10000)
    dn = S.quantise(x, 12, 0.0, 10.0)
    assert dn.dtype == np.uint16 and dn.max() <= 4095
    back = S.dequantise(dn, 12, 0.0, 10.0)
    step = 10.0 / 4095
    assert np.max(np.abs(back - x)) <= 0.5 * step * (1 + 1e-12)
    # uniform error: rms step / sqrt(12) within 3 %
    assert np.sqrt(np.mean((back - x) ** 2)) == pytest.approx(step / math.sqrt(12), rel=0.03)
    assert S.quantise(np.array([-1.0, 11.0]), 12, 0.0, 10.0).tolist() == [0, 4095]


def test_sensor_spec_validation():
    with pytest.raises(InputError, match="focal_length_m"):
        S.SensorSpec(focal_length_m=-1.0)
    with pytest.raises(InputError, match="optics_transmittance"):
        S.SensorSpec(optics_transmittance=0.0)


def test_degree_interface_equals_the_radian_formulas():
    # the public angles are degrees; the results equal the closed forms evaluated in radians
    re, h = S.EARTH_RADIUS_M, S.PAPER_SENSOR.altitude_m
    deg = np.array([0.0, 10.0, 45.0, 70.0])
    th = np.radians(deg)
    np.testing.assert_allclose(S.slant_range(deg, h),
                               np.sqrt((re + h) ** 2 - (re * np.sin(th)) ** 2) - re * np.cos(th),
                               rtol=1e-14)
    np.testing.assert_allclose(S.slant_range(deg, h, None), h / np.cos(th), rtol=1e-14)
    az = np.radians(120.0)
    np.testing.assert_allclose(enu_direction(deg, 120.0),
                               np.stack([np.sin(th) * np.sin(az), np.sin(th) * np.cos(az),
                                         np.cos(th)], axis=-1), atol=1e-15)
    with pytest.raises(InputError):
        S.slant_range(90.0, h)  # the horizon: no ground intersection
