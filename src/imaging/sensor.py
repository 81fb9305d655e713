"""Space-based sensor: geometry, camera equation, sub-pixel mixing, PSF, noise, quantisation.

Paper §5 sensor: 795 km orbit, focal length 1.06 m, aperture 0.53 m (f-number 2.0),
40 um pixels, optics transmittance 0.7. Nadir ground sample distance
``GSD = H p / f = 795e3 * 40e-6 / 1.06 = 30.0 m``.

Data flow: surface-leaving radiance -> (eq. 1) at-aperture radiance
(:func:`at_aperture_radiance`) -> focal-plane irradiance (:func:`focal_plane_irradiance`)
-> optional PSF (:func:`apply_psf`), noise (:func:`add_netd_noise`) and quantisation
(:func:`quantise`). Sub-pixel mixing of ship and background (paper §3.1) is the area-weighted
mean (:func:`mix_subpixel`, :func:`pixel_average`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.special import j1

from shipthermal.errors import InputError, check_finite, check_positive, check_range, require

from .parameters import PAPER_SENSOR_PARAMETERS

__all__ = [
    "SensorSpec", "PAPER_SENSOR", "ground_sample_distance", "slant_range",
    "at_aperture_radiance", "focal_plane_irradiance", "mix_subpixel",
    "pixel_average", "optical_transfer_function", "apply_psf", "psf_kernel",
    "add_netd_noise", "quantise", "dequantise",
]

EARTH_RADIUS_M = 6371.0e3
"""Mean Earth radius [m] (IUGG mean radius R1)."""


@dataclass(frozen=True)
class SensorSpec:
    """Sensor and orbit parameters (defaults: paper §5,
    :data:`imaging.parameters.PAPER_SENSOR_PARAMETERS`).

    Attributes
    ----------
    altitude_m : float
        Orbit altitude above the surface [m].
    focal_length_m : float
        Effective focal length [m].
    aperture_m : float
        Entrance-pupil diameter [m].
    pixel_pitch_m : float
        Detector pixel pitch (square pixels, 100 % fill factor) [m].
    optics_transmittance : float
        Optics transmittance tau_o [-].
    """

    altitude_m: float = PAPER_SENSOR_PARAMETERS["altitude_m"]
    focal_length_m: float = PAPER_SENSOR_PARAMETERS["focal_length_m"]
    aperture_m: float = PAPER_SENSOR_PARAMETERS["aperture_m"]
    pixel_pitch_m: float = PAPER_SENSOR_PARAMETERS["pixel_pitch_m"]
    optics_transmittance: float = PAPER_SENSOR_PARAMETERS["optics_transmittance"]

    def __post_init__(self):
        for name in ("altitude_m", "focal_length_m", "aperture_m", "pixel_pitch_m"):
            check_positive(f"sensor.{name}", getattr(self, name), "m")
        check_range("sensor.optics_transmittance", self.optics_transmittance, 0.0, 1.0,
                    low_open=True)

    @property
    def f_number(self) -> float:
        """Focal ratio N = f / D [-]."""
        return self.focal_length_m / self.aperture_m

    @property
    def nadir_gsd_m(self) -> float:
        """Nadir ground sample distance ``H p / f`` [m]."""
        return self.altitude_m * self.pixel_pitch_m / self.focal_length_m


PAPER_SENSOR = SensorSpec()
"""The paper's sensor (§5): GSD 30.0 m, N = 2.0."""


def slant_range(view_zenith, altitude_m: float, earth_radius_m: float | None = EARTH_RADIUS_M):
    """Sensor-to-ground distance [m] for a view zenith angle at the ground [deg].

    ``altitude_m`` [m]; ``earth_radius_m`` [m] or None for a flat Earth (``H / cos theta``).
    Spherical Earth: ``R = sqrt((Re + H)^2 - Re^2 sin^2 theta) - Re cos theta``.
    """
    check_range("view_zenith", view_zenith, 0.0, 90.0, "deg", high_open=True)
    theta = np.radians(np.asarray(view_zenith, dtype=float))
    if earth_radius_m is None:
        return altitude_m / np.cos(theta)
    re = earth_radius_m
    return np.sqrt((re + altitude_m) ** 2 - (re * np.sin(theta)) ** 2) - re * np.cos(theta)


def ground_sample_distance(spec: SensorSpec = PAPER_SENSOR, view_zenith=0.0,
                           earth_radius_m: float | None = EARTH_RADIUS_M):
    """Ground sample distance in and across the view plane [m].

    Parameters
    ----------
    spec : SensorSpec
        Sensor.
    view_zenith : array_like
        View zenith angle at the ground [deg] (0 = nadir).
    earth_radius_m : float or None
        Earth radius [m]; None for a flat Earth.

    Returns
    -------
    (numpy.ndarray, numpy.ndarray)
        ``(gsd_along_view_azimuth, gsd_across)`` [m]. Nadir: both ``H p / f`` (30.0 m for
        the paper's sensor).

    Notes
    -----
    One pixel subtends the angle ``p / f``; at slant range ``R`` it covers ``R p / f``
    across the view plane and ``R p / (f cos theta)`` along it (the ground is inclined by
    the view zenith ``theta`` to the line of sight; on a sphere ``ds/d alpha = R / cos
    theta`` too). Flat Earth: ``H p / (f cos^2 theta)`` and ``H p / (f cos theta)``.
    """
    r = slant_range(view_zenith, spec.altitude_m, earth_radius_m)
    across = r * spec.pixel_pitch_m / spec.focal_length_m
    return across / np.cos(np.radians(np.asarray(view_zenith, dtype=float))), across


def at_aperture_radiance(leaving_radiance, transmittance, path_radiance):
    """At-aperture band radiance, paper eq. 1: ``L = tau_a L_surface + L_path``.

    ``leaving_radiance`` [W m-2 sr-1] (target or background, eq. 2), ``transmittance``
    [-] slant-path band transmittance, ``path_radiance`` [W m-2 sr-1]. Returns
    [W m-2 sr-1]. (Band-integrated: exact when tau_a is spectrally flat over the band, the
    usual band-model approximation; the atmosphere module owns the band averages.)
    """
    return (np.asarray(transmittance, dtype=float) * leaving_radiance
            + np.asarray(path_radiance, dtype=float))


def focal_plane_irradiance(radiance, spec: SensorSpec = PAPER_SENSOR, field_angle=0.0,
                           model: str = "aplanatic"):
    """Focal-plane irradiance from at-aperture radiance (camera equation).

    Parameters
    ----------
    radiance : array_like
        At-aperture band radiance [W m-2 sr-1].
    spec : SensorSpec
        Sensor (uses tau_o and N = f / D).
    field_angle : array_like
        Off-axis field angle [deg] for the ``cos^4`` fall-off (0 on axis).
    model : {"aplanatic", "thin_lens"}
        "aplanatic": ``E = tau_o pi L / (4 N^2)`` (exact for an aplanatic system, i.e. one
        obeying Abbe's sine condition with ``N = 1 / (2 sin u')``, object at infinity).
        "thin_lens": ``E = tau_o pi L / (1 + 4 N^2)`` (cone of half angle ``u'`` with
        ``tan u' = 1/(2N)``). For N = 2 they differ by 6 %.

    Returns
    -------
    numpy.ndarray
        Irradiance on the detector [W m-2].

    Notes
    -----
    Standard camera equation ``E = tau_o pi L sin^2 u' cos^4(field angle)``; e.g. Schott,
    Remote Sensing: The Image Chain Approach (2007), §5.2; Slater, Remote Sensing: Optics
    and Optical Systems (1980). Paper sensor: ``pi * 0.7 / 16 = 0.137`` m2 sr per m2 sr.
    Pixel power: ``E * pixel_pitch_m**2`` [W].
    """
    n = spec.f_number
    if model == "aplanatic":
        geom = 1.0 / (4.0 * n * n)
    elif model == "thin_lens":
        geom = 1.0 / (1.0 + 4.0 * n * n)
    else:
        raise InputError("model", model, "must be 'aplanatic' or 'thin_lens'")
    c4 = np.cos(np.radians(np.asarray(field_angle, dtype=float))) ** 4
    return spec.optics_transmittance * math.pi * geom * c4 * np.asarray(radiance, dtype=float)


def mix_subpixel(coverage_fraction, L_target, L_background):  # noqa: N803 (names from brief)
    """Area-weighted pixel radiance of a target partly covering a pixel (paper §3.1).

    Parameters
    ----------
    coverage_fraction : array_like
        Fraction of the pixel's ground footprint covered by the target [-], in [0, 1].
    L_target : array_like
        Mean radiance of the target part [W m-2 sr-1].
    L_background : array_like
        Mean radiance of the uncovered part [W m-2 sr-1].

    Returns
    -------
    numpy.ndarray
        ``a L_t + (1 - a) L_b`` [W m-2 sr-1]: a detector integrates flux, so a uniform
        pixel response mixes radiances linearly by area.
    """
    a = np.asarray(coverage_fraction, dtype=float)
    check_range("coverage_fraction", a, 0.0, 1.0)
    return a * np.asarray(L_target, dtype=float) + (1.0 - a) * np.asarray(L_background,
                                                                         dtype=float)


def pixel_average(supersampled, samples_per_pixel: int):
    """Block-mean an image rendered at ``samples_per_pixel`` x ``samples_per_pixel`` samples
    per pixel [same unit as input]: the uniform-response detector integral (e.g. Embree
    render at >= 16 x 16 rays per 30 m pixel). Also turns a 0/1 ship mask into coverage [-].
    """
    img = np.asarray(supersampled, dtype=float)
    s = int(samples_per_pixel)
    require(s >= 1, "samples_per_pixel", samples_per_pixel, "must be >= 1")
    ny, nx = img.shape[0] // s, img.shape[1] // s
    require(img.shape[0] == ny * s and img.shape[1] == nx * s, "supersampled", img.shape,
            f"both dimensions must be multiples of samples_per_pixel={s}")
    return img.reshape(ny, s, nx, s, *img.shape[2:]).mean(axis=(1, 3))


# ---------------------------------------------------------------------------------------
# PSF
# ---------------------------------------------------------------------------------------
def optical_transfer_function(freq_x, freq_y, wavelength_um: float,
                              spec: SensorSpec = PAPER_SENSOR, include_detector: bool = True):
    """System OTF (real, >= 0 here): diffraction of a clear circular aperture x pixel box.

    Parameters
    ----------
    freq_x, freq_y : array_like
        Spatial frequencies in the focal plane in cycles per pixel pitch [1/pixel].
    wavelength_um : float
        Wavelength for diffraction [um] (band-mean wavelength for a band).
    spec : SensorSpec
        Sensor (N and pixel pitch).
    include_detector : bool
        Multiply by the pixel-box MTF ``|sinc(fx) sinc(fy)|``.

    Returns
    -------
    numpy.ndarray
        OTF [-], 1 at zero frequency.

    Notes
    -----
    Incoherent diffraction MTF of a circular pupil (Goodman, Introduction to Fourier
    Optics, §6.3): ``(2/pi)(acos s - s sqrt(1 - s^2))``, ``s = nu / nu_c``,
    ``nu_c = 1 / (lambda N)``. Its Fourier pair is the Airy pattern
    ``[2 J1(x)/x]^2``, ``x = pi r / (lambda N)``. Paper sensor: ``nu_c`` = 5.0 cycles per
    40 um pixel at 4 um, 1.8 at 11 um (Nyquist is 0.5).
    """
    fx = np.asarray(freq_x, dtype=float)
    fy = np.asarray(freq_y, dtype=float)
    nu_c = spec.pixel_pitch_m / (wavelength_um * 1e-6 * spec.f_number)
    s = np.minimum(np.hypot(fx, fy) / nu_c, 1.0)
    otf = (2.0 / math.pi) * (np.arccos(s) - s * np.sqrt(1.0 - s * s))
    if include_detector:
        otf = otf * np.sinc(fx) * np.sinc(fy)
    return otf


def apply_psf(image, wavelength_um: float, spec: SensorSpec = PAPER_SENSOR,
              samples_per_pixel: float = 1, include_detector: bool = False):
    """Blur an image with the diffraction PSF (Airy pattern) by FFT.

    Parameters
    ----------
    image : array_like
        2-D image [any unit] sampled at ``samples_per_pixel`` samples per detector pitch.
    wavelength_um : float
        Diffraction wavelength [um] (band-mean wavelength for a band).
    spec : SensorSpec
        Sensor.
    samples_per_pixel : float
        Image samples per detector pixel pitch [-] (an integer for a supersampled render; a
        ratio > 1 for a product grid finer than the detector's ground footprint, e.g.
        Landsat TIRS's 99 m pixels on its 30 m product grid).
    include_detector : bool
        Also blur with the detector's box (its pixel-integration MTF): for a product grid
        finer than the detector, where no block mean does it.

    Returns
    -------
    numpy.ndarray
        Blurred image, same unit; the mean is preserved (OTF(0) = 1).

    Notes
    -----
    Exact detector signal = (scene * Airy * pixel box) sampled at pixel centres. With a
    supersampled render do ``pixel_average(apply_psf(render, lam, spec, s), s)``: the block
    mean is the pixel box. On a pixel-sampled image (``samples_per_pixel=1``) the result is
    the usual band-limited approximation (the Airy OTF of the paper's sensor extends to 5.0
    cycles/pixel at 4 um, beyond the 0.5 Nyquist). The image is reflect-padded by 8 pixels
    (the Airy wings beyond carry < 0.5 % of the energy) before the periodic FFT.
    """
    img = np.asarray(image, dtype=float)
    require(img.ndim == 2, "image", img.shape, "must be 2-D")
    s = float(samples_per_pixel)
    require(s >= 1.0, "samples_per_pixel", samples_per_pixel, "must be >= 1")
    pad = int(np.ceil(8 * s))
    big = np.pad(img, pad, mode="reflect")
    fy = s * np.fft.fftfreq(big.shape[0])[:, None]   # cycles per detector pitch
    fx = s * np.fft.rfftfreq(big.shape[1])[None, :]
    otf = optical_transfer_function(fx, fy, wavelength_um, spec,
                                    include_detector=include_detector)
    out = np.fft.irfft2(np.fft.rfft2(big) * otf, s=big.shape)
    return out[pad:-pad, pad:-pad]


def psf_kernel(wavelength_um: float, spec: SensorSpec = PAPER_SENSOR, half_width: int = 3,
               oversample: int = 15):
    """Pixel-integrated PSF (Airy pattern convolved with the pixel box), direct quadrature.

    Parameters
    ----------
    wavelength_um : float
        Wavelength [um].
    spec : SensorSpec
        Sensor.
    half_width : int
        Kernel is ``(2 half_width + 1)^2`` pixels [-].
    oversample : int
        Midpoint samples per pixel per axis [-].

    Returns
    -------
    numpy.ndarray
        Fraction of a centred point source's energy landing on each pixel [-]; sums to the
        ensquared energy of the window (< 1: the Airy wings outside are not renormalised).

    Notes
    -----
    ``PSF(r) = [2 J1(x)/x]^2 pi / (4 (lambda N)^2)`` per unit area, ``x = pi r / (lambda N)``
    (normalised to unit integral; Born & Wolf §8.5.2).
    """
    check_positive("wavelength_um", wavelength_um, "um")
    lam_n = wavelength_um * 1e-6 * spec.f_number / spec.pixel_pitch_m  # in pixels
    n = 2 * half_width + 1
    m = n * oversample
    c = (np.arange(m) + 0.5) / oversample - n / 2.0
    r = np.hypot(c[:, None], c[None, :])
    x = np.maximum(math.pi * r / lam_n, 1e-12)
    psf = (2.0 * j1(x) / x) ** 2 * math.pi / (4.0 * lam_n**2)
    return psf.reshape(n, oversample, n, oversample).sum(axis=(1, 3)) / oversample**2


# ---------------------------------------------------------------------------------------
# Noise and quantisation
# ---------------------------------------------------------------------------------------
def add_netd_noise(signal, netd_k: float, responsivity, seed: int | None = 0):
    """Add white Gaussian detector noise specified by a NETD.

    Parameters
    ----------
    signal : array_like
        Clean image [W m-2 sr-1 or W m-2].
    netd_k : float
        Noise-equivalent temperature difference [K] (e.g. 0.05).
    responsivity : float or array_like
        ``d signal / d T`` of a blackbody scene at the reference temperature, in the
        signal's unit per K (e.g. :func:`shipthermal.optics.planck.band_radiance_dt` at 300 K,
        times the camera factor when the signal is irradiance).
    seed : int or None
        Seed of numpy's default generator (reproducible images); None for fresh noise.

    Returns
    -------
    numpy.ndarray
        Noisy image, same unit: ``signal + N(0, (NETD * responsivity)^2)``.
    """
    check_positive("netd_k", netd_k, "K")
    sig = np.asarray(signal, dtype=float)
    rng = np.random.default_rng(seed)
    return sig + netd_k * np.asarray(responsivity, dtype=float) * rng.standard_normal(sig.shape)


def quantise(signal, bits: int, vmin: float, vmax: float):
    """Uniform quantiser: digital numbers ``round((s - vmin) / step)``, clipped.

    ``signal`` [any unit], ``bits`` [-] (1-32), ``vmin``/``vmax`` [signal unit] mapped to 0
    and ``2^bits - 1``. Returns unsigned integer DNs (uint16 up to 16 bits, else uint32).
    Quantisation noise is ``step / sqrt(12)`` with ``step = (vmax - vmin)/(2^bits - 1)``.
    """
    require(1 <= int(bits) <= 32, "bits", bits, "must be in 1..32")
    require(vmax > vmin, "vmax", vmax, f"must exceed vmin={vmin}")
    levels = 2 ** int(bits) - 1
    s = np.asarray(signal, dtype=float)
    check_finite("signal", s)
    dn = np.rint((s - vmin) / (vmax - vmin) * levels)
    return np.clip(dn, 0, levels).astype(np.uint16 if bits <= 16 else np.uint32)


def dequantise(dn, bits: int, vmin: float, vmax: float):
    """Inverse of :func:`quantise`: DN -> signal [vmin..vmax unit]."""
    levels = 2 ** int(bits) - 1
    return vmin + np.asarray(dn, dtype=float) * (vmax - vmin) / levels
