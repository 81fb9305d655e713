"""The six LOWTRAN 7 model atmospheres, their scaling to a day's weather, and the site rule.

Models (Kneizys et al. 1988, AFGL-TR-88-0177, card 1 ``MODEL``; profiles of Anderson et al.
1986, AFGL-TR-86-0110): 1 tropical, 2 mid-latitude summer, 3 mid-latitude winter,
4 sub-arctic summer, 5 sub-arctic winter, 6 US standard 1976. ``"summer"`` and
``"winter"`` name the paper's two (mid-latitude summer / winter, its MODTRAN settings).

Scaling to the weather (LOWTRAN's own mechanism: a user atmosphere, ``MODEL=7``, card 2C1)
-----------------------------------------------------------------------------------------
LOWTRAN 7 has no switch that scales a model's water vapour or temperature; its way of
taking other conditions is a user profile read level by level (card 2C1), where ``JCHAR``
lets every gas not given default to a model atmosphere. :func:`model_profile` writes such a
profile from the chosen model for a near-surface air temperature ``T_air`` [K] and relative
humidity ``RH`` [%]:

* temperature ``T(z) = T_m(z) + ΔT max(0, 1 − z / 2 km)``, ``ΔT = T_air − T_m(0)``
  (ASSUMPTION: the screen-level departure spans the marine boundary layer, taken as the
  0–2 km of LOWTRAN's boundary-layer aerosol, and fades linearly across it);
* water vapour ``w(z) = s w_m(z)``: the model's column scaled by one factor (as MODTRAN's
  ``H2OSTR``) chosen so that the surface relative humidity LOWTRAN computes (subroutine
  ``AERNSM``, saturation density ``a exp(18.9766 − 14.9595 a − 2.43882 a²)`` g m⁻³,
  ``a = 273.15/T``) equals ``RH``; no cap at saturation aloft (LOWTRAN needs none);
* every other gas: the model's (``JCHAR``), levels as LOWTRAN lays them out for the model
  (subroutine ``FLAYZ``): 0–25 km by 1 km, 30, 35, 40, 45, 50, 70, 100 km; with a cloud deck
  the cloud levels 0–6 km and 7–100 km.

The Navy maritime aerosol follows: LOWTRAN takes its humidity from the profile's surface
level (so it is ``RH``) and the winds from card 2.

The site rule (:func:`model_for_site`)
--------------------------------------
With the day's mean air temperature known (a weather record): the model whose surface air
temperature is closest to it. LOWTRAN's own model surface temperatures are tropical
299.7 K, mid-latitude summer 294.2, mid-latitude winter 272.2, sub-arctic summer 287.2,
sub-arctic winter 257.2, US 1976 288.2 (``BLOCK DATA MLATMB``; MODTRAN lists the same, US
1976 as 288.15). This is the criterion behind the MODTRAN/FLAASH guidance table (Table 2
of the ENVI FLAASH user's guide: "suggested MODTRAN model atmospheres based on
latitudinal/seasonal dependence of surface temperature") applied to the day itself; it
also keeps the scaling (``ΔT``) small. Without a temperature the FLAASH table
(latitude rows every 10°, months Jan/Mar/May/Jul/Sep/Nov, nearest row and month) is used.
A day more than :data:`MAX_TEMP_OFFSET_K` from every model cannot be placed.

A weather record of weeks to a year is placed day by day
(:func:`model_for_record_day`): each local day gets the model of its own mean air temperature
and month, so a winter overpass is seen through a winter atmosphere and a summer one through
a summer atmosphere; an extreme day beyond every model's reach gets the nearest model (its
offset clamped by the tables, as for a named model) and is reported, not refused.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from shipthermal.errors import InputError, check_range

from ..parameters import ATMOSPHERE_MODELS
from ..parameters import CLOUD_TYPES as _CLOUD_NAMES
from . import aerosol as aer
from .lowtran_cards import Profile

__all__ = ["AtmosphereState", "CLOUD_TYPES", "MODEL_NUMBERS", "MODEL_NAMES", "PAPER_LABELS",
           "MAX_TEMP_OFFSET_K", "BOUNDARY_LAYER_KM", "model_name", "model_label", "model_number",
           "SurfaceState", "surface_state", "model_profile", "water_vapour_scale",
           "model_for_site", "model_for_record_day", "earth_radius_km", "aerosol_season",
           "default_wind_speed",
           "FLAASH_TABLE"]

MODEL_NUMBERS = {name: i + 1 for i, name in enumerate(ATMOSPHERE_MODELS)}
"""LOWTRAN 7 ``MODEL`` number of each model atmosphere."""
MODEL_NAMES = tuple(MODEL_NUMBERS)
PAPER_LABELS = {"midlatitude_summer": "summer", "midlatitude_winter": "winter"}
"""The paper's names of its two model atmospheres (kept as labels of results and products)."""
_ALIASES = {"summer": "midlatitude_summer", "winter": "midlatitude_winter",
            "mid-latitude summer": "midlatitude_summer", "mid-latitude winter":
            "midlatitude_winter", "mls": "midlatitude_summer", "mlw": "midlatitude_winter",
            "trp": "tropical", "sas": "subarctic_summer", "saw": "subarctic_winter",
            "us76": "us_standard_1976", "us_1976": "us_standard_1976",
            **{str(n): name for name, n in MODEL_NUMBERS.items()}}
BOUNDARY_LAYER_KM = 2.0
"""Depth over which the screen-level temperature departure fades [km] (ASSUMPTION, see
the module notes)."""
MAX_TEMP_OFFSET_K = 20.0
"""Largest |air temperature − model surface temperature| the tables hold [K]."""
_EARTH_RADIUS = {1: 6378.39, 4: 6356.91, 5: 6356.91}  # LOWTRAN's per-model radius [km]
CLEAR_LEVELS_KM = np.array([*range(26), 30, 35, 40, 45, 50, 70, 100], dtype=float)
CLOUD_LEVELS_KM = np.array([0.0, 0.16, 0.33, 0.66, 1.0, 1.5, 2.0, 2.4, 2.7, 3.0, 3.5, 4.0, 4.5,
                            5.0, 5.5, 6.0, 7, 8, 9, 10, 12, 14, 16, 18, 20, 22, 25, 30, 35, 40,
                            50, 70, 100])
CLOUD_TYPES = {name: i + 1 for i, name in enumerate(_CLOUD_NAMES)}
"""LOWTRAN 7 cloud decks (card 2 ``ICLD``; Kneizys et al. 1988, §3.4): cumulus base 0.66 km
top 2.7 km (3.0 with its last level), altostratus 2.4-3.0, stratus 0.33-1.0, stratocumulus
0.66-2.0, nimbostratus 0.16-0.66 km; liquid water content per level in ``BLOCK DATA``
(``CLD1``-``CLD5``)."""
#: Liquid water content [g m⁻³] of each deck on the first 10 cloud levels (``CLD1``-``CLD5``)
CLOUD_LWC = {1: (0.0, 0.0, 0.0, 0.2, 0.35, 1.0, 1.0, 1.0, 0.3, 0.15),
             2: (0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.3, 0.4, 0.3),
             3: (0.0, 0.0, 0.15, 0.30, 0.15, 0.0, 0.0, 0.0, 0.0, 0.0),
             4: (0.0, 0.0, 0.0, 0.10, 0.15, 0.15, 0.10, 0.0, 0.0, 0.0),
             5: (0.0, 0.30, 0.65, 0.40, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)}

# ENVI FLAASH user's guide, Table 2 (MODTRAN model atmospheres by latitude and month)
_FLAASH_MONTHS = (1, 3, 5, 7, 9, 11)
_T, _MS, _MW, _SS, _SW = ("tropical", "midlatitude_summer", "midlatitude_winter",
                          "subarctic_summer", "subarctic_winter")
FLAASH_TABLE = {
    80: (_SW, _SW, _SW, _MW, _MW, _SW), 70: (_SW, _SW, _MW, _MW, _MW, _SW),
    60: (_MW, _MW, _MW, _SS, _SS, _MW), 50: (_MW, _MW, _SS, _SS, _SS, _SS),
    40: (_SS, _SS, _SS, _MS, _MS, _SS), 30: (_MS, _MS, _MS, _T, _T, _MS),
    20: (_T,) * 6, 10: (_T,) * 6, 0: (_T,) * 6, -10: (_T,) * 6,
    -20: (_T, _T, _T, _MS, _MS, _T), -30: (_MS,) * 6, -40: (_SS,) * 6,
    -50: (_SS, _SS, _SS, _MW, _MW, _SS), -60: (_MW,) * 6, -70: (_MW,) * 6, -80: (_MW,) * 6}
"""Model atmosphere by latitude row [deg] and month (Jan, Mar, May, Jul, Sep, Nov)."""


def model_name(model) -> str:
    """Canonical name of a model atmosphere (a name of :data:`MODEL_NAMES`, an alias such
    as ``"summer"``/``"winter"``/``"mls"``, or the LOWTRAN number 1-6)."""
    key = str(model).strip().lower().replace(" ", "_") if not isinstance(model, str) \
        else model.strip().lower()
    key = _ALIASES.get(key, _ALIASES.get(key.replace("_", " "), key))
    if key not in MODEL_NUMBERS:
        raise InputError("model", model, f"must be one of {', '.join(MODEL_NAMES)} (or "
                         "'summer' / 'winter', the paper's mid-latitude summer / winter)",
                         "Name one of LOWTRAN 7's six model atmospheres")
    return key


def model_number(model) -> int:
    """LOWTRAN ``MODEL`` number (1-6)."""
    return MODEL_NUMBERS[model_name(model)]


def model_label(model) -> str:
    """Label of results and products: the paper's ``"summer"``/``"winter"`` for its two
    models, else the model's name."""
    name = model_name(model)
    return PAPER_LABELS.get(name, name)


def earth_radius_km(model) -> float:
    """Earth radius LOWTRAN uses with the model [km] (card 3 ``RO`` default)."""
    return _EARTH_RADIUS.get(model_number(model), 6371.23)


def aerosol_season(model) -> int:
    """LOWTRAN ``ISEASN`` of the model: 2 (fall-winter) for the winter models, else 1."""
    return 2 if model_number(model) in (3, 5) else 1


def default_wind_speed(model) -> float:
    """LOWTRAN 7's Navy maritime default wind of the model (subroutine ``MARINE``) [m s⁻¹]."""
    return float(aer.DEFAULT_WIND_SPEED[model_number(model)])


@dataclass(frozen=True)
class AtmosphereState:
    """The day's conditions a model atmosphere is scaled to (None: the model's own).

    Attributes
    ----------
    temp_air_K : float or None
        Near-surface air temperature [K] (None: the model's surface temperature).
    rel_humidity : float or None
        Near-surface relative humidity [%] (None: the model's surface humidity).
    wind_speed : float or None
        Wind at 10 m [m s⁻¹], LOWTRAN's current and 24-h wind of the Navy maritime aerosol
        (None: LOWTRAN 7's default for the model).
    vis_km : float
        Meteorological range [km] (the tables hold 23 km, the paper's).
    """

    temp_air_K: float | None = None
    rel_humidity: float | None = None
    wind_speed: float | None = None
    vis_km: float = 23.0

    def __post_init__(self):
        if self.temp_air_K is not None:
            check_range("temp_air", self.temp_air_K, 200.0, 340.0, "K")
        if self.rel_humidity is not None:
            check_range("relative_humidity", self.rel_humidity, 0.0, 100.0, "%",
                        low_open=True)
        if self.wind_speed is not None:
            check_range("wind_speed", self.wind_speed, 0.0, 50.0, "m/s")
        check_range("vis_km", self.vis_km, 0.5, 100.0, "km")

    @property
    def is_default(self) -> bool:
        """True when nothing departs from the model's own state."""
        return (self.temp_air_K is None and self.rel_humidity is None
                and self.wind_speed is None and self.vis_km == 23.0)

    def offsets(self, model) -> tuple[float, float]:
        """``(ΔT [K], water-vapour scale [-])`` of the scaled profile for ``model``."""
        if self.temp_air_K is None and self.rel_humidity is None:
            return 0.0, 1.0
        s = surface_state(model)
        t = s.temp_air_K if self.temp_air_K is None else float(self.temp_air_K)
        rh = s.rel_humidity if self.rel_humidity is None else float(self.rel_humidity)
        return t - s.temp_air_K, water_vapour_scale(model, t, rh)

    def wind(self, model) -> float:
        """Navy maritime wind [m s⁻¹] for ``model``."""
        return default_wind_speed(model) if self.wind_speed is None else float(self.wind_speed)

    def surface_humidity(self, model) -> float:
        """Relative humidity [%] at the surface of the scaled profile (the aerosol's)."""
        return surface_state(model).rel_humidity if self.rel_humidity is None \
            else float(self.rel_humidity)


@dataclass(frozen=True)
class SurfaceState:
    """Surface level of a model atmosphere: air temperature [K], relative humidity [%],
    pressure [mb] and water-vapour mixing ratio [ppmv]."""

    temp_air_K: float
    rel_humidity: float
    pressure_mb: float
    h2o_ppmv: float


def _sat_density(temp_K):
    """LOWTRAN's saturation water-vapour density [g m⁻³] (subroutine ``AERNSM``)."""
    a = 273.15 / np.asarray(temp_K, dtype=float)
    return a * np.exp(18.9766 - 14.9595 * a - 2.43882 * a * a)


def _vapour_density(ppmv, pressure_mb, temp_K):
    """Water-vapour density [g m⁻³] of a mixing ratio [ppmv] (LOWTRAN ``CONVRT``)."""
    n_air = 2.68675e19 * (pressure_mb / 1013.25) * (273.15 / temp_K)  # [cm-3]
    return ppmv * 1e-6 * n_air * 18.015 / 6.022045e23 * 1e6


@lru_cache(maxsize=8)
def _model_arrays(number: int):
    t = aer.load_aerosol_tables()
    i = number - 1
    return (np.asarray(t["model_alt_km"], dtype=float), np.asarray(t["model_pressure_mb"][i]),
            np.asarray(t["model_temp_k"][i]), np.asarray(t["model_h2o_ppmv"][i]))


def surface_state(model) -> SurfaceState:
    """Surface air temperature, humidity, pressure and water vapour of a model atmosphere."""
    z, p, t, w = _model_arrays(model_number(model))
    rh = 100.0 * float(_vapour_density(w[0], p[0], t[0]) / _sat_density(t[0]))
    return SurfaceState(float(t[0]), rh, float(p[0]), float(w[0]))


def water_vapour_scale(model, temp_air_K: float, rel_humidity: float) -> float:
    """Factor on the model's water-vapour column that gives the surface ``rel_humidity``
    [%] at ``temp_air_K`` [K] (LOWTRAN's saturation density and air density)."""
    s = surface_state(model)
    rho = rel_humidity / 100.0 * float(_sat_density(temp_air_K))
    ppmv = rho / float(_vapour_density(1.0, s.pressure_mb, temp_air_K))
    return ppmv / s.h2o_ppmv


def _lagrange4(z_nodes, values, z_query):
    """LOWTRAN's interpolation of a model atmosphere to a level (subroutine ``DEFALT``):
    the cubic through the four nodes around it (log pressure, temperature, mixing ratio)."""
    out = np.empty(len(z_query))
    n = len(z_nodes)
    for k, zq in enumerate(z_query):
        i2 = 1 + int(np.searchsorted(z_nodes[1:], zq, side="left"))
        i2 = min(i2, n - 1)
        idx = [i2 - 2, i2 - 1, i2, i2 + 1]
        if idx[0] < 0:
            idx = [i + 1 for i in idx]
        elif idx[3] > n - 1:
            idx = [i - 1 for i in idx]
        zz, vv = z_nodes[idx], values[idx]
        out[k] = sum(vv[j] * np.prod([(zq - zz[m]) / (zz[j] - zz[m]) for m in range(4) if m != j])
                     for j in range(4))
    return out


def model_profile(model, temp_offset_K: float = 0.0, h2o_scale: float = 1.0,
                  cloud_type: int = 0) -> Profile:
    """LOWTRAN user atmosphere (card 2C1) of a model shifted by ``temp_offset_K`` [K] at
    the surface (fading to 0 at :data:`BOUNDARY_LAYER_KM`) with its water vapour scaled by
    ``h2o_scale`` [-]; levels as LOWTRAN lays out the model, with a cloud deck
    ``cloud_type`` (``ICLD`` 1-5, 0 none) on the cloud levels and saturated inside the
    cloud as LOWTRAN makes it for a model atmosphere (``AERNSM``: RH = 100 % where the
    liquid water content is positive; for a user atmosphere it leaves the humidity as
    given).
    """
    number = model_number(model)
    z, p, t, w = _model_arrays(number)
    levels = CLOUD_LEVELS_KM if cloud_type else CLEAR_LEVELS_KM
    pl = np.exp(_lagrange4(z, np.log(p), levels))
    tl = _lagrange4(z, t, levels) + temp_offset_K * np.clip(1.0 - levels / BOUNDARY_LAYER_KM,
                                                            0.0, 1.0)
    wl = _lagrange4(z, w, levels) * h2o_scale
    if cloud_type:
        inside = np.flatnonzero(np.asarray(CLOUD_LWC[int(cloud_type)]) > 0.0)
        wl[inside] = (_sat_density(tl[inside])
                      / _vapour_density(1.0, pl[inside], tl[inside]))
    return Profile(levels, pl, tl, wl, number)


def model_for_record_day(latitude_deg: float, month: int, temp_air_mean_K: float
                         ) -> tuple[str, bool]:
    """:func:`model_for_site` for one local day of a weather record, and whether the day lay
    more than :data:`MAX_TEMP_OFFSET_K` from every model's surface temperature.

    Such a day gets the nearest model (the tables then clamp its offset, as for a named
    model) instead of an error: one extreme day must not stop a year's run; the caller
    reports it.
    """
    temps = [surface_state(name).temp_air_K for name in MODEL_NAMES]
    lo, hi = min(temps) - MAX_TEMP_OFFSET_K, max(temps) + MAX_TEMP_OFFSET_K
    t = float(temp_air_mean_K)
    return model_for_site(latitude_deg, month, min(max(t, lo), hi)), not lo <= t <= hi


def model_for_site(latitude_deg: float, month: int, temp_air_mean_K: float | None = None
                   ) -> str:
    """The model atmosphere of a site and month (see the module notes for the rule).

    Parameters
    ----------
    latitude_deg : float
        Site latitude, north positive [deg].
    month : int
        Month of the day (1-12).
    temp_air_mean_K : float, optional
        The day's mean near-surface air temperature [K]: picks the model with the closest
        surface temperature; None: the FLAASH latitude/month table.

    Returns
    -------
    str
        A name of :data:`MODEL_NAMES`.
    """
    check_range("latitude_deg", latitude_deg, -90.0, 90.0, "deg")
    if int(month) != month or not 1 <= int(month) <= 12:
        raise InputError("month", month, "must be an integer 1-12")
    if temp_air_mean_K is None:
        row = int(np.clip(10 * round(latitude_deg / 10.0), -80, 80))
        # nearest tabulated month, cyclically (Dec -> Nov/Jan: Jan; Feb -> Jan/Mar: Jan)
        dist = [min(abs(month - m), 12 - abs(month - m)) for m in _FLAASH_MONTHS]
        return FLAASH_TABLE[row][int(np.argmin(dist))]
    temps = {name: surface_state(name).temp_air_K for name in MODEL_NAMES}
    best = min(temps, key=lambda n: abs(temps[n] - temp_air_mean_K))
    if abs(temps[best] - temp_air_mean_K) > MAX_TEMP_OFFSET_K:
        lo, hi = min(temps.values()), max(temps.values())
        raise InputError("weather (day-mean air temperature)", round(float(temp_air_mean_K), 1),
                         f"must lie within {MAX_TEMP_OFFSET_K:g} K of a model atmosphere's "
                         f"surface temperature ({lo:g}-{hi:g} K), the range of the "
                         "atmosphere tables", "Check the weather's temperature unit, or name "
                         "a model in [imaging.atmosphere] model (its offset is then clamped)")
    return best
