"""Real and user sensors: optics, bands, noise, quantisation and their products.

An :class:`Instrument` is a :class:`imaging.sensor.SensorSpec` (orbit altitude, focal
length, aperture, pixel pitch → ground sample distance and diffraction + pixel PSF) with
bands (:class:`InstrumentBand`: spectral response, noise-equivalent temperature
difference, quantisation and the product's brightness-temperature definition).

Presets (:data:`PRESETS`), each number labelled with its origin:

``"paper"``
    The paper's generic instrument (§5): 795 km, f 1.06 m, D 0.53 m, 40 µm pixels
    (30.0 m GSD), rectangular 3-5 / 8-14 µm bands; no NETD or quantisation stated.
``"landsat8_tirs"``
    Landsat-8 TIRS: 705 km; telescope f 178 mm, aperture 108 mm (f/1.64), 25 µm QWIP
    pixels → 99 m GSD (Reuter et al. 2015, Remote Sens. 7:1135, TIRS instrument); bands
    10 (measured response, USGS) and 11 (published edges, rectangular); on-orbit NETD
    0.05 K at 300 K (Montanaro et al. 2014, Remote Sens. 6:11753); 12-bit; Level-1
    product: 16-bit DN, ``L = 3.342e-4 Q + 0.1`` W m⁻² sr⁻¹ µm⁻¹, ``BT = K2 / ln(K1/L +
    1)`` with K1 = 774.8853 / 480.8883, K2 = 1321.0789 / 1201.1442 (band 10 / 11; Level-1
    MTL, LANDSAT_8 product metadata).
``"landsat9_tirs2"``
    Landsat-9 TIRS-2: same telescope and orbit as TIRS; bands at the published edges
    (ASSUMPTION: rectangular, no response table at hand); NETD 0.05 K (ASSUMPTION: as
    TIRS); 14-bit; product ``L = 3.8e-4 Q + 0.1`` (band 10), ``3.49e-4 Q + 0.1`` (band
    11); K1 = 799.0284 / 475.6581, K2 = 1329.2405 / 1198.3494 (Landsat-9 Level-1 MTL).
``"sdgsat1_tis"``
    SDGSAT-1 Thermal Infrared Spectrometer: 505 km, 30 m GSD, bands 8.0-10.5,
    10.3-11.3, 11.5-12.5 µm (rectangular, ASSUMPTION), NETD 0.2 K at 300 K (mission
    specification); ASSUMPTION: 25 µm pixels (focal length from the GSD, 0.42 m), f/2,
    12-bit over 0-25 W m⁻² sr⁻¹ µm⁻¹; products in radiance and brightness temperature by
    inverting the band's Planck integral (no K1/K2 published here).
``"ecostress"``
    ECOSTRESS PHyTIR on the ISS: ~400 km, 70 m product GSD (38 m × 69 m native),
    five thermal bands (Gaussian, ASSUMPTION, :mod:`shipthermal.optics.responses`), NETD 0.15 K
    (ASSUMPTION, the mission's reported on-orbit order), 14-bit; ASSUMPTION: 40 µm
    pixels, f/2 (focal length from the GSD).

A user's instrument (:func:`user_instrument`) takes a response table per band, the
optics and the detector.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from shipthermal.errors import InputError, check_positive, require
from shipthermal.optics.planck import band_radiance, band_radiance_dt, brightness_temperature
from shipthermal.optics.responses import (SpectralResponse, named_band, read_response_file,
                                          user_band_names)

from .parameters import SENSOR_PRESETS
from .sensor import SensorSpec

__all__ = ["InstrumentBand", "Instrument", "PRESETS", "PRESET_NAMES", "instrument",
           "user_instrument", "product_radiance", "product_brightness_temperature",
           "band_mean_radiance", "to_dn", "from_dn", "noise_sigma", "k1k2_difference",
           "band_product"]


@dataclass(frozen=True)
class InstrumentBand:
    """One band of an instrument.

    Attributes
    ----------
    key : str
        Band key of the atmosphere tables (:data:`shipthermal.optics.responses.BAND_NAMES`) or
        the user band's name.
    response : SpectralResponse
        Relative spectral response [-] on wavelength [µm].
    netd_K : float or None
        Noise-equivalent temperature difference at 300 K [K] (None: not stated).
    bits : int or None
        Quantisation of the product (None: none).
    radiance_range : tuple or None
        ``(L_min, L_max)`` band-mean spectral radiance [W m⁻² sr⁻¹ µm⁻¹] mapped to DN 1 and
        ``2^bits − 1`` (the product's rescaling).
    k1, k2 : float or None
        The product's brightness-temperature constants [W m⁻² sr⁻¹ µm⁻¹], [K]
        (``BT = K2 / ln(K1 / L + 1)``); None: the band's Planck integral is inverted.
    source : str
        Where the numbers come from.
    """

    key: str
    response: SpectralResponse
    netd_K: float | None = None
    bits: int | None = None
    radiance_range: tuple | None = None
    k1: float | None = None
    k2: float | None = None
    source: str = ""

    @property
    def width_um(self) -> float:
        """∫R dλ [µm]: band radiance ÷ this = band-mean spectral radiance."""
        w, _ = self.response.quadrature(8)
        return float(np.sum(w))


@dataclass(frozen=True)
class Instrument:
    """A sensor: optics and orbit (:class:`SensorSpec`) and its bands."""

    name: str
    spec: SensorSpec
    bands: tuple
    source: str = ""
    notes: dict = field(default_factory=dict)

    @property
    def band_keys(self) -> tuple:
        return tuple(b.key for b in self.bands)

    def band(self, key: str) -> InstrumentBand:
        for b in self.bands:
            if b.key == key:
                return b
        raise InputError("band", key, f"must be one of {list(self.band_keys)} of "
                         f"instrument {self.name!r}")

    @property
    def nadir_gsd_m(self) -> float:
        """Nadir ground sample distance ``H p / f`` [m]."""
        return self.spec.nadir_gsd_m


def _spec_from_gsd(altitude_m, gsd_m, pitch_m, f_number, tau_o=0.7) -> SensorSpec:
    f = altitude_m * pitch_m / gsd_m
    return SensorSpec(altitude_m=altitude_m, focal_length_m=f, aperture_m=f / f_number,
                      pixel_pitch_m=pitch_m, optics_transmittance=tau_o)


def _landsat(name, k, mult, tirs2: bool):
    bands = []
    for key, k1, k2, m in k:
        bands.append(InstrumentBand(
            key=key, response=named_band(key), netd_K=0.05, bits=14 if tirs2 else 12,
            radiance_range=(m * 1 + 0.1, m * 65535 + 0.1), k1=k1, k2=k2,
            source="Level-1 MTL rescaling and thermal constants"))
    spec = SensorSpec(altitude_m=705e3, focal_length_m=0.178, aperture_m=0.1085,
                      pixel_pitch_m=25e-6, optics_transmittance=0.7)
    return Instrument(name, spec, tuple(bands), source="Landsat-8/9 TIRS; see module notes",
                      notes={"optics_transmittance": "ASSUMPTION 0.7 (as the paper's)"})


PRESETS = {
    "paper": Instrument(
        "paper", SensorSpec(),
        tuple(InstrumentBand(b, named_band(b), source="paper §5, rectangular")
              for b in ("3-5", "8-14")), source="paper §5"),
    "landsat8_tirs": _landsat("landsat8_tirs", [
        ("landsat8_tirs_b10", 774.8853, 1321.0789, 3.342e-4),
        ("landsat8_tirs_b11", 480.8883, 1201.1442, 3.342e-4)], None, False),
    "landsat9_tirs2": _landsat("landsat9_tirs2", [
        ("landsat9_tirs2_b10", 799.0284, 1329.2405, 3.8e-4),
        ("landsat9_tirs2_b11", 475.6581, 1198.3494, 3.49e-4)], None, True),
    "sdgsat1_tis": Instrument(
        "sdgsat1_tis", _spec_from_gsd(505e3, 30.0, 25e-6, 2.0),
        tuple(InstrumentBand(f"sdgsat1_tis_b{i}", named_band(f"sdgsat1_tis_b{i}"), netd_K=0.2,
                             bits=12, radiance_range=(0.0, 25.0),
                             source="mission specification; ASSUMPTION shape and rescaling")
              for i in (1, 2, 3)), source="SDGSAT-1 TIS; see module notes"),
    "ecostress": Instrument(
        "ecostress", _spec_from_gsd(400e3, 70.0, 40e-6, 2.0),
        tuple(InstrumentBand(f"ecostress_b{i}", named_band(f"ecostress_b{i}"), netd_K=0.15,
                             bits=14, radiance_range=(0.0, 25.0),
                             source="ASSUMPTION shape, NETD and rescaling")
              for i in range(1, 6)), source="ECOSTRESS PHyTIR; see module notes"),
}
"""The instrument presets (see the module notes for every number's origin)."""
PRESET_NAMES = SENSOR_PRESETS


def instrument(name: str) -> Instrument:
    """A preset instrument by name (:data:`PRESET_NAMES`)."""
    if name not in PRESETS:
        raise InputError("imaging.sensor.preset", name, f"must be one of "
                         f"{', '.join(PRESET_NAMES)} or 'user'",
                         "Name a preset, or give preset = 'user' with response_files and "
                         "the optics")
    return PRESETS[name]


def user_instrument(name: str, response_files: dict, spec: SensorSpec,
                    netd_K: float | None = None, bits: int | None = None,
                    radiance_range: tuple | None = None) -> Instrument:
    """An instrument from the user's response tables (``{band name: path}``) and optics."""
    require(isinstance(response_files, dict) and response_files, "response_files",
            response_files, "must map band names to response files")
    bands = tuple(InstrumentBand(str(k), read_response_file(v, str(k)), netd_K=netd_K,
                                 bits=bits, radiance_range=radiance_range,
                                 source=f"user response file {v}")
                  for k, v in response_files.items())
    return Instrument(name, spec, bands, source="user")


def band_product(key: str) -> InstrumentBand:
    """The :class:`InstrumentBand` of a named band: the preset's that holds it (its product
    definitions), or a plain one for the paper's rectangles."""
    for inst in PRESETS.values():
        for b in inst.bands:
            if b.key == key:
                return b
    source = "user response" if key in user_band_names() else "named band"
    return InstrumentBand(key, named_band(key), source=source)


# ------------------------------------------------------------------------- products
def band_mean_radiance(band_radiance_value, band: InstrumentBand):
    """Band-mean spectral radiance ``∫L R dλ / ∫R dλ`` [W m⁻² sr⁻¹ µm⁻¹] of a band
    radiance [W m⁻² sr⁻¹] (the unit of Landsat's products)."""
    return np.asarray(band_radiance_value, dtype=float) / band.width_um


def product_radiance(band_radiance_value, band: InstrumentBand):
    """The product's radiance: band-mean spectral radiance [W m⁻² sr⁻¹ µm⁻¹]."""
    return band_mean_radiance(band_radiance_value, band)


def product_brightness_temperature(band_radiance_value, band: InstrumentBand):
    """Brightness temperature [K] as the sensor's product defines it: ``K2 / ln(K1/L + 1)``
    on the band-mean spectral radiance ``L`` where the product publishes K1/K2 (Landsat),
    else the inverse of the band's Planck integral with its response
    (:func:`shipthermal.optics.planck.brightness_temperature`)."""
    if band.k1 is not None and band.k2 is not None:
        lm = np.maximum(band_mean_radiance(band_radiance_value, band), 1e-12)
        return band.k2 / np.log(band.k1 / lm + 1.0)
    return brightness_temperature(np.maximum(np.asarray(band_radiance_value, dtype=float),
                                             1e-9), band.response)


def to_dn(band_radiance_value, band: InstrumentBand):
    """Digital numbers of the product's rescaling: ``Q = round((L − L_min) / g) + 1`` with
    ``g = (L_max − L_min) / (2^bits − 2)``, clipped to 1..2^bits − 1 (Landsat: 16-bit
    products, ``L = ML Q + AL``)."""
    require(band.bits is not None and band.radiance_range is not None, "band", band.key,
            "has no quantisation")
    lm = band_mean_radiance(band_radiance_value, band)
    lo, hi = band.radiance_range
    top = 2 ** (16 if band.k1 is not None else int(band.bits)) - 1
    g = (hi - lo) / (top - 1)
    return np.clip(np.rint((lm - lo) / g) + 1, 1, top).astype(np.uint32)


def from_dn(dn, band: InstrumentBand):
    """Band radiance [W m⁻² sr⁻¹] of digital numbers (inverse of :func:`to_dn`)."""
    lo, hi = band.radiance_range
    top = 2 ** (16 if band.k1 is not None else int(band.bits)) - 1
    g = (hi - lo) / (top - 1)
    return (lo + (np.asarray(dn, dtype=float) - 1) * g) * band.width_um


def noise_sigma(band: InstrumentBand, transmittance: float = 1.0, temp_K: float = 300.0):
    """Standard deviation of the detector noise in band radiance [W m⁻² sr⁻¹]: the NETD
    times ``τ dL/dT`` of a blackbody at ``temp_K`` seen through ``transmittance``."""
    require(band.netd_K is not None, "band", band.key, "has no NETD")
    check_positive("transmittance", transmittance)
    return float(band.netd_K * transmittance * band_radiance_dt(temp_K, band.response))


def k1k2_difference(band: InstrumentBand, temps=(240.0, 340.0)) -> dict:
    """How far the product's K1/K2 brightness temperature is from the true temperature of a
    blackbody seen in the band (its radiance from the response table): max |BT − T|, mean
    and value at 300 K [K] over ``temps`` [K]. K1/K2 is itself a fit to the response."""
    t = np.linspace(*temps, 101)
    bt = product_brightness_temperature(band_radiance(t, band.response), band)
    d = bt - t
    return {"max_abs_K": float(np.max(np.abs(d))), "mean_K": float(np.mean(d)),
            "at_300K": float(np.interp(300.0, t, d))}

