"""Named sensor bands: the paper's rectangles and real thermal instruments' bands.

Each name maps to a :class:`SpectralResponse` (relative response,
piecewise linear between knots, zero outside). Where a measured response table is at hand
it is used; elsewhere the band is built from its published edges (or centre and width)
and the assumed shape is stated with it (:data:`BAND_SOURCES`).

The embedded atmosphere tables hold band values for every name here
(:mod:`imaging.atmosphere.tables`); any other response (a user's table) is integrated
from the tables' spectra.

Bands
-----
``"3-5"``, ``"8-14"``
    The paper's rectangles [µm] (§5).
``"landsat8_tirs_b10"``
    Landsat-8 TIRS band 10, measured relative spectral response (USGS; public domain),
    ``data/landsat8_tirs_b10_rsr.csv``.
``"landsat8_tirs_b11"``, ``"landsat9_tirs2_b10"``, ``"landsat9_tirs2_b11"``
    Published band edges 11.50-12.51 / 10.60-11.19 / 11.50-12.51 µm (USGS Landsat 8/9
    band designations); ASSUMPTION: rectangular between the edges.
``"sdgsat1_tis_b1"`` … ``"_b3"``
    SDGSAT-1 Thermal Infrared Spectrometer, 8.0-10.5, 10.3-11.3, 11.5-12.5 µm (CBAS
    SDGSAT-1 mission description); ASSUMPTION: rectangular.
``"ecostress_b1"`` … ``"_b5"``
    ECOSTRESS PHyTIR thermal bands, centres 8.29, 8.78, 9.20, 10.49, 12.09 µm with full
    widths at half maximum 0.354, 0.310, 0.396, 0.410, 0.611 µm (as-built values of the
    mission's Level-1 documentation; to be replaced by the mission's response files where
    at hand); ASSUMPTION: Gaussian, cut at 2 FWHM from the centre.
"""

from __future__ import annotations

import csv
from contextlib import contextmanager
from dataclasses import dataclass
from functools import lru_cache
from importlib import resources

import numpy as np

from shipthermal.errors import InputError, check_positive, check_range, require
from shipthermal.parameters import BANDS

from .quadrature import gauss_legendre

__all__ = ["SpectralResponse", "rectangular_response", "BAND_NAMES", "BAND_SOURCES", "named_band",
           "is_named_band", "read_response_file", "response_from_table", "thermal_band_of",
           "thermal_band_key", "nominal_range", "user_bands", "user_band_names"]

@dataclass(frozen=True)
class SpectralResponse:
    """Relative spectral response of a sensor band, piecewise linear between knots.

    Attributes
    ----------
    name : str
        Band label, e.g. ``"3-5"``.
    wavelength_um : numpy.ndarray
        Strictly increasing knot wavelengths [um]. The response is zero outside
        ``[wavelength_um[0], wavelength_um[-1]]``.
    response : numpy.ndarray
        Relative response at the knots [-], in [0, 1].
    """

    name: str
    wavelength_um: np.ndarray
    response: np.ndarray

    def __post_init__(self):
        wl = np.array(self.wavelength_um, dtype=float)
        rs = np.array(self.response, dtype=float)
        require(wl.ndim == 1 and wl.size >= 2, f"response[{self.name}].wavelength_um", wl,
                "must be a 1-D table with at least 2 knots")
        require(rs.shape == wl.shape, f"response[{self.name}].response", rs,
                f"must have the same length as wavelength_um ({wl.size})")
        check_positive(f"response[{self.name}].wavelength_um", wl, "um")
        require(bool(np.all(np.diff(wl) > 0)), f"response[{self.name}].wavelength_um", wl,
                "must be strictly increasing", "Sort the table by wavelength")
        check_range(f"response[{self.name}].response", rs, 0.0, 1.0)
        wl.setflags(write=False)
        rs.setflags(write=False)
        object.__setattr__(self, "wavelength_um", wl)
        object.__setattr__(self, "response", rs)

    @property
    def mean_wavelength_um(self) -> float:
        """Response-weighted mean wavelength [um] (e.g. for the diffraction PSF)."""
        w, x = self.quadrature(4)
        return float(np.sum(w * x) / np.sum(w))

    def quadrature(self, nodes_per_segment: int = 8) -> tuple[np.ndarray, np.ndarray]:
        """Gauss-Legendre weights and nodes for ``int R(lambda) g(lambda) d lambda``.

        Returns ``(weights [um], nodes [um])``; the response (linear on each segment) is
        folded into the weights, so ``sum(weights * g(nodes))`` is the band integral of
        ``g``. Exact for ``g`` polynomial of degree ``2 n - 2`` on each segment.
        """
        xg, wg = gauss_legendre(int(nodes_per_segment))
        a, b = self.wavelength_um[:-1, None], self.wavelength_um[1:, None]
        ra, rb = self.response[:-1, None], self.response[1:, None]
        half = 0.5 * (b - a)
        nodes = 0.5 * (a + b) + half * xg[None, :]
        t = 0.5 * (xg[None, :] + 1.0)
        weights = half * wg[None, :] * (ra + (rb - ra) * t)
        keep = weights.ravel() != 0.0
        return weights.ravel()[keep], nodes.ravel()[keep]


def rectangular_response(low_um: float, high_um: float, name: str | None = None
                         ) -> SpectralResponse:
    """Rectangular (ideal) band response: 1 on ``[low_um, high_um]`` [um], 0 outside."""
    require(float(high_um) > float(low_um) > 0, "band", (low_um, high_um),
            "needs 0 < low_um < high_um [um]")
    return SpectralResponse(name or f"{low_um:g}-{high_um:g}", np.array([low_um, high_um]),
                            np.array([1.0, 1.0]))


NAMED_BANDS: dict[str, tuple[str, object, str]] = {
    "3-5": ("rectangle", BANDS["3-5"], "SOURCED: paper §5, rectangular 3-5 um"),
    "8-14": ("rectangle", BANDS["8-14"], "SOURCED: paper §5, rectangular 8-14 um"),
    "landsat8_tirs_b10": ("table", "landsat8_tirs_b10_rsr.csv",
                          "SOURCED: USGS measured relative spectral response (public domain)"),
    "landsat8_tirs_b11": ("rectangle", (11.50, 12.51),
                          "ASSUMPTION: rectangular at the published edges 11.50-12.51 um"),
    "landsat9_tirs2_b10": ("rectangle", (10.60, 11.19),
                           "ASSUMPTION: rectangular at the published edges 10.60-11.19 um"),
    "landsat9_tirs2_b11": ("rectangle", (11.50, 12.51),
                           "ASSUMPTION: rectangular at the published edges 11.50-12.51 um"),
    "sdgsat1_tis_b1": ("rectangle", (8.0, 10.5),
                       "ASSUMPTION: rectangular at the published edges 8.0-10.5 um"),
    "sdgsat1_tis_b2": ("rectangle", (10.3, 11.3),
                       "ASSUMPTION: rectangular at the published edges 10.3-11.3 um"),
    "sdgsat1_tis_b3": ("rectangle", (11.5, 12.5),
                       "ASSUMPTION: rectangular at the published edges 11.5-12.5 um"),
    **{k: ("gaussian", (c, w), f"ASSUMPTION: Gaussian, centre {c} um, FWHM {w} um, cut at "
                               "2 FWHM")
       for k, (c, w) in {"ecostress_b1": (8.29, 0.354), "ecostress_b2": (8.78, 0.310),
                         "ecostress_b3": (9.20, 0.396), "ecostress_b4": (10.49, 0.410),
                         "ecostress_b5": (12.09, 0.611)}.items()},
}
"""Every named band, one entry each: ``name: (shape, parameters, source)`` with shape
``"rectangle"`` (edges [µm]), ``"gaussian"`` (centre and FWHM [µm]) or ``"table"`` (a
measured response file in ``data/``). A new named band is one entry here (and its file, if
measured); the atmosphere tables then need regenerating to hold it
(``scripts/make_atmosphere_tables.py``)."""

_RECT = {k: v for k, (shape, v, _) in NAMED_BANDS.items() if shape == "rectangle"}
_GAUSS = {k: v for k, (shape, v, _) in NAMED_BANDS.items() if shape == "gaussian"}
_TABLES = {k: v for k, (shape, v, _) in NAMED_BANDS.items() if shape == "table"}

#: Every named band, in a fixed order (the order of the atmosphere tables' band axis)
BAND_NAMES = tuple(NAMED_BANDS)

#: Where each band's response comes from, and what shape is assumed
BAND_SOURCES = {k: source for k, (_, _, source) in NAMED_BANDS.items()}

#: Wavelength limits [µm] a response must lie within (the atmosphere tables' range)
RESPONSE_RANGE_UM = (2.9, 14.5)


def _gaussian(centre: float, fwhm: float, name: str) -> SpectralResponse:
    sigma = fwhm / (2.0 * np.sqrt(2.0 * np.log(2.0)))
    wl = np.linspace(centre - 2.0 * fwhm, centre + 2.0 * fwhm, 81)
    return SpectralResponse(name, wl, np.exp(-0.5 * ((wl - centre) / sigma) ** 2))


def response_from_table(name: str, wavelength_um, response) -> SpectralResponse:
    """A :class:`SpectralResponse` from a table, checked and scaled to a peak of 1.

    Raises :class:`InputError` (naming the band) for negative or non-increasing
    wavelengths, negative responses, an all-zero response or a table outside the
    atmosphere tables' 2.9-14.5 µm.
    """
    wl = np.asarray(wavelength_um, dtype=float)
    r = np.asarray(response, dtype=float)
    key = f"response[{name}]"
    require(wl.ndim == 1 and wl.size >= 2 and r.shape == wl.shape, key, wl.shape,
            "needs two columns of equal length with at least 2 rows (wavelength [um], "
            "relative response)")
    require(bool(np.all(np.isfinite(wl)) and np.all(np.isfinite(r))), key, "non-finite value",
            "must hold finite numbers only")
    require(bool(np.all(wl > 0.0)), f"{key}.wavelength_um", float(wl.min()),
            "must be positive [um]", "Give wavelengths in micrometres")
    require(bool(np.all(np.diff(wl) > 0.0)), f"{key}.wavelength_um", "not increasing",
            "must increase strictly from row to row", "Sort the table by wavelength and "
            "remove repeated wavelengths")
    require(bool(np.all(r >= 0.0)), f"{key}.relative_response", float(r.min()),
            "must not be negative")
    require(float(r.max()) > 0.0, f"{key}.relative_response", 0.0, "must not be all zero")
    lo, hi = RESPONSE_RANGE_UM
    support = wl[r > 0.0]
    require(support[0] >= lo and support[-1] <= hi, f"{key}.wavelength_um",
            (float(support[0]), float(support[-1])),
            f"the response must lie inside {lo}-{hi} um (the atmosphere tables' range)",
            "Trim the zero-response rows outside the band, or use a band inside "
            f"{lo}-{hi} um")
    return SpectralResponse(name, wl, r / r.max())


def read_response_file(path, name: str | None = None) -> SpectralResponse:
    """Read a relative spectral response: two columns, wavelength [µm] and response [-].

    Whitespace- or comma-separated; lines starting with ``#`` and a non-numeric header line
    are skipped. Checked by :func:`response_from_table`.
    """
    from pathlib import Path

    p = Path(path)
    if not p.is_file():
        raise InputError("response_file", str(path), "must be an existing file",
                         "Give the path of a two-column table (wavelength [um], response)")
    rows = []
    for i, line in enumerate(p.read_text(encoding="utf-8").splitlines()):
        text = line.strip()
        if not text or text.startswith("#"):
            continue
        parts = text.replace(",", " ").split()
        try:
            rows.append((float(parts[0]), float(parts[1])))
        except (ValueError, IndexError):
            if rows:
                raise InputError("response_file", f"{p.name} line {i + 1}: {text!r}",
                                 "must hold two numbers per line (wavelength [um], "
                                 "response)") from None
    return response_from_table(name or p.stem, [r[0] for r in rows], [r[1] for r in rows])


@lru_cache(maxsize=None)  # immutable package data, read once
def _table_band(name: str) -> SpectralResponse:
    ref = resources.files("shipthermal.optics") / "data" / _TABLES[name]
    with resources.as_file(ref) as path:
        with open(path, encoding="utf-8") as f:
            rows = [r for r in csv.reader(line for line in f if not line.startswith("#"))]
    wl = [float(r[0]) for r in rows[1:]]
    rr = [float(r[1]) for r in rows[1:]]
    return response_from_table(name, wl, rr)


_USER_BANDS: dict = {}
"""The user bands in force (:func:`user_bands`): ``{name: SpectralResponse}``."""


def user_band_names() -> tuple:
    """Names of the user bands in force (:func:`user_bands`), besides :data:`BAND_NAMES`."""
    return tuple(_USER_BANDS)


@contextmanager
def user_bands(responses):
    """Let a user sensor's bands be named like the built-in ones inside the block.

    The imaging run passes bands by name (file names, tables, metrics); a user's response
    (e.g. ``[imaging.sensor] preset = "user"``) is taken by :func:`named_band` under its
    name while the block runs, and the atmosphere integrates it from its tables' spectra
    (:func:`imaging.atmosphere.resolve_band`).

    Parameters
    ----------
    responses : iterable of SpectralResponse
        Each is known by its ``name``, which must not be one of :data:`BAND_NAMES`; a name
        already in force must carry the same response (nested blocks of the same sensor).
    """
    added = []
    try:
        for resp in responses:
            require(isinstance(resp, SpectralResponse), "user band", resp,
                    "must be a SpectralResponse (shipthermal.optics.responses.read_response_file)")
            require(resp.name not in BAND_NAMES, "user band", resp.name,
                    f"must not be a named band ({', '.join(BAND_NAMES)})",
                    "Give the user band another name")
            old = _USER_BANDS.get(resp.name)
            if old is None:
                _USER_BANDS[resp.name] = resp
                added.append(resp.name)
            else:
                require(old.wavelength_um.shape == resp.wavelength_um.shape
                        and bool(np.array_equal(old.wavelength_um, resp.wavelength_um))
                        and bool(np.array_equal(old.response, resp.response)),
                        "user band", resp.name, "is already in force with another response",
                        "Give the two sensors' bands different names")
        yield tuple(_USER_BANDS)
    finally:
        for name in added:
            _USER_BANDS.pop(name, None)


def is_named_band(name) -> bool:
    """True for a name of :data:`BAND_NAMES`."""
    return isinstance(name, str) and name in BAND_NAMES


def named_band(name: str) -> SpectralResponse:
    """The :class:`SpectralResponse` of a named band (:data:`BAND_NAMES`)."""
    if not isinstance(name, str):
        raise InputError("band", name, f"must be one of {', '.join(BAND_NAMES)}")
    if name in _RECT:
        return rectangular_response(*_RECT[name], name=name)
    if name in _GAUSS:
        return _gaussian(*_GAUSS[name], name)
    if name in _TABLES:
        return _table_band(name)
    if name in _USER_BANDS:
        return _USER_BANDS[name]
    raise InputError("band", name, f"must be one of {', '.join(BAND_NAMES)}",
                     "Or give the sensor's response table")


def nominal_range(response: SpectralResponse) -> tuple[float, float]:
    """Half-maximum edges of a response [µm] (the edges of a rectangle): the band as a
    ``(lo, hi)`` range, e.g. for the emissivity tables of the paper's bands."""
    wl, r = response.wavelength_um, response.response
    above = np.flatnonzero(r >= 0.5 * r.max())
    i, j = int(above[0]), int(above[-1])

    def cross(a, b):
        if r[a] == r[b]:
            return float(wl[a])
        return float(wl[a] + (0.5 * r.max() - r[a]) * (wl[b] - wl[a]) / (r[b] - r[a]))

    lo = float(wl[i]) if i == 0 else cross(i - 1, i)
    hi = float(wl[j]) if j == wl.size - 1 else cross(j, j + 1)
    return round(lo, 3), round(hi, 3)


def thermal_band_key(band) -> str:
    """``"3-5"`` or ``"8-14"``: the paper band whose emissivity tables stand for ``band``
    (a band name or a :class:`SpectralResponse`)."""
    if isinstance(band, str) and band in ("3-5", "8-14"):
        return band
    return thermal_band_of(band if isinstance(band, SpectralResponse) else named_band(band))


def thermal_band_of(response: SpectralResponse) -> str:
    """The paper band (``"3-5"`` or ``"8-14"``) holding most of a response: the band whose
    emissivities and water optics stand for it."""
    w, x = response.quadrature(4)
    mean = float(np.sum(w * x) / np.sum(w))
    return "3-5" if mean < 6.5 else "8-14"
