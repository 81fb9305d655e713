"""Built-in climatological design days for the port of Dalian (summer and winter).

Two days, mid-July and mid-January, at Dalian (Liaoning, China; 38.91 N, 121.63 E,
UTC+8; the Yellow Sea / Bohai coast). Every number below carries its source and one of
three labels:

* SOURCED   — a climate statistic copied from the cited source;
* DERIVED   — computed from sourced numbers by a stated published method;
* ASSUMPTION — our choice where no source was at hand; change it if you have data.

The numbers were fixed from these sources before any comparison with the paper's
reference deck temperatures, and must not be tuned to them.

Sources
-------
[A] Monthly normals of Dalian station (CMA): mean, mean daily maximum and minimum air
    temperature per month, as tabulated in the Baidu Baike entry "大连" (climate
    section) and reproduced in "大连气候特点" (cqtresearch.com, 2023-05-27). The
    averaging period is not stated there, and the same table has an evident typo
    (May mean 18.5 between Apr 9.1 and Jun 19.4), so treat it as a secondary source.
    Not checked against the CMA 1991–2020 normals (not reachable offline). Jul:
    mean 23.0, max 26.0, min 20.7 degC; Jan: mean −4.9, max −1.2, min −8.2 degC.
[B] weather-atlas.com, "Dalian, China – climate": mean relative humidity from 55 %
    "at the outset of the year" (taken as January) to 84 % "in the midst of the
    summer monsoon" (taken as July); sea temperature from
    2.8 degC in winter to a peak of 23.6 degC in August.
[C] weather2visit.com, "Dachangshandao" (island station of Dalian's Changhai
    County in the northern Yellow Sea): mean daily sunshine 7.4 h in July, 6.8 h in January
    (also used to cross-check [A]: Jul max/min 26.8/20.9, Jan −2.3/−10.3 degC).
[D] Dalian climate summary (Baidu Baike, as [A]): northerly monsoon prevails in
    winter, southerly in summer.
[E] Parton, W. J. & Logan, J. A. (1981), "A model for diurnal variation in soil and
    air temperature", Agric. Meteorol. 23, 205–216: sine by day, exponential decay at
    night; coefficients for air at 150 cm a = 1.86 h, b = 2.20, c = −0.17 h.
[F] Wu, Z. et al. (2020), Ocean Sci. 16, 83–97: offshore China SST lowest in
    February, highest in August; Advances in Meteorology (2016), article 3820720,
    30 years of NOAA OISST 1/4-degree daily SST over the Bohai, Yellow and East China
    Seas: > 90 % of the temporal SST variance is the annual harmonic.
[G] Kawai, Y. & Wada, A. (2007), J. Oceanogr. 63, 721–744: diurnal SST range of a
    few tenths of a kelvin, larger only in calm sunny weather; small in winter.
"""

from __future__ import annotations

import dataclasses
from typing import Dict, Optional, Tuple

import numpy as np
import pandas as pd
from scipy.optimize import brentq

from shipthermal.errors import InputError
from shipthermal.parameters import DALIAN, DESIGN_DAY_DATES
from shipthermal.units import ZERO_CELSIUS

from .sea import sst_diurnal
from .sky import relative_humidity_from_dew_point
from .sun import sunrise_sunset
from .weather import Weather

__all__ = ["ClimateDay", "DALIAN", "dalian_summer", "dalian_winter", "climate_day",
           "parton_logan", "annual_harmonic_sst"]

# Parton & Logan (1981) Table 1, air temperature at 150 cm [E]
PL_A, PL_B, PL_C = 1.86, 2.20, -0.17


def parton_logan(hour, temp_min, temp_max, sunrise, sunset, a=PL_A, b=PL_B, c=PL_C):
    """Diurnal air temperature between a daily minimum and maximum [E].

    Parameters
    ----------
    hour : array_like
        Local clock time [h] (24 h periodic).
    temp_min, temp_max : float
        Daily minimum and maximum temperature [K].
    sunrise, sunset : float
        Local clock times of sunrise and sunset [h].
    a : float
        Lag of the maximum after solar noon [h].
    b : float
        Night-time decay coefficient [-].
    c : float
        Lag of the minimum after sunrise [h].

    Returns
    -------
    numpy.ndarray
        Temperature [K]; the minimum ``temp_min`` occurs at sunrise + c and the
        maximum ``temp_max`` at sunrise + c + (Y + 2a)/2 (Y = day length).

    Notes
    -----
    Day (Parton & Logan 1981 eq. 1): T = Tn + (Tx − Tn) sin(π m / (Y + 2a)), m hours
    after the minimum. Night: exponential decay from the sunset value Tsn with their
    coefficient b, written as T = [Tn − Tsn e^−b + (Tsn − Tn) e^(−b n / Z)] / (1 − e^−b)
    (n hours after sunset, Z the time from sunset to the next minimum) so the curve
    reaches Tn exactly at the next minimum and the day is periodic; the original
    eq. 2 stops ≈ 0.11 (Tsn − Tn) short of Tn.
    """
    h = np.mod(np.asarray(hour, dtype=float), 24.0)
    y = sunset - sunrise
    t_min_at = sunrise + c
    m = h - t_min_at
    day = (m >= 0.0) & (h <= sunset)
    t_day = temp_min + (temp_max - temp_min) * np.sin(np.pi * m / (y + 2.0 * a))
    tsn = temp_min + (temp_max - temp_min) * np.sin(np.pi * (sunset - t_min_at) / (y + 2.0 * a))
    z = 24.0 - sunset + t_min_at
    n = np.mod(h - sunset, 24.0)
    eb = np.exp(-b)
    t_night = (temp_min - tsn * eb + (tsn - temp_min) * np.exp(-b * n / z)) / (1.0 - eb)
    return np.where(day, t_day, t_night)


def annual_harmonic_sst(month, sst_min, sst_max, month_min=2.0, month_max=8.0):
    """SST on a mid-month date from its annual extremes by a single annual harmonic [F].

    Parameters
    ----------
    month : float
        Month number of the date (e.g. 7 for mid-July) [-].
    sst_min, sst_max : float
        Climatological minimum and maximum monthly SST [K].
    month_min, month_max : float
        Months of the extremes (February and August for the China seas [F]).

    Returns
    -------
    float
        ``mean − A cos(2π (m − m_min) / 12)`` with mean and A from the extremes [K].
        (The extremes are 6 months apart, as a pure annual harmonic requires.)
    """
    if abs(abs(month_max - month_min) - 6.0) > 1e-9:
        raise InputError("month_max", month_max, "must be 6 months after month_min")
    mean = 0.5 * (sst_min + sst_max)
    amp = 0.5 * (sst_max - sst_min)
    return mean - amp * np.cos(2.0 * np.pi * (month - month_min) / 12.0)


@dataclasses.dataclass(frozen=True)
class ClimateDay:
    """A climatological design day (all temperatures in K).

    ``sources`` maps each field to (label, citation); labels are SOURCED, DERIVED or
    ASSUMPTION (module docstring).
    """

    name: str
    date: str
    latitude: float
    longitude: float
    altitude: float
    tz: str
    temp_max: float
    temp_min: float
    temp_mean_source: float
    relative_humidity_mean: float
    sunshine_hours: float
    wind_speed: float
    wind_direction: float
    temp_sea_mean: float
    sst_amplitude: float
    sources: Dict[str, Tuple[str, str]]
    cloud_cover_override: Optional[float] = None

    def sun_times(self):
        """Sunrise, transit, sunset [local h] by SPA."""
        return sunrise_sunset(self.date, self.latitude, self.longitude, self.tz)

    @property
    def day_length(self) -> float:
        """Astronomical day length [h] (SPA sunrise to sunset)."""
        rise, _, sset = self.sun_times()
        return sset - rise

    @property
    def cloud_cover(self) -> float:
        """Cloud fraction = 1 − relative sunshine duration [-] (DERIVED, see sources),
        unless ``cloud_cover_override`` is set."""
        if self.cloud_cover_override is not None:
            return float(self.cloud_cover_override)
        return float(np.clip(1.0 - self.sunshine_hours / self.day_length, 0.0, 1.0))

    def perturbed(self, wind=0.0, air=0.0, cloud=0.0) -> "ClimateDay":
        """A copy with shifted wind [m/s], air temperature [K] and cloud cover [-].

        For sensitivity tables (wind ±1 m/s, air ±1 K, cloud ±0.2): the whole diurnal
        air-temperature curve moves by ``air`` (Tmin and Tmax both), wind speed is
        clipped at 0 and cloud cover to [0, 1]; the relative humidity keeps its mean.
        """
        return dataclasses.replace(
            self, name=f"{self.name}{'' if not (wind or air or cloud) else '*'}",
            wind_speed=max(self.wind_speed + wind, 0.0),
            temp_max=self.temp_max + air, temp_min=self.temp_min + air,
            cloud_cover_override=None if cloud == 0.0 else
            float(np.clip(self.cloud_cover + cloud, 0.0, 1.0)))

    def temp_air(self, hour):
        """Air temperature [K] at local clock hours (Parton & Logan [E])."""
        rise, _, sset = self.sun_times()
        return parton_logan(hour, self.temp_min, self.temp_max, rise, sset)

    def dew_point(self) -> float:
        """Constant dew point [K] whose diurnal-mean RH equals the sourced mean RH.

        ASSUMPTION: the vapour pressure is constant through the day, so RH follows
        the temperature cycle (a common first approximation; dew point varies much
        less than air temperature on a day without fronts).
        """
        hours = np.arange(0.0, 24.0, 0.1)
        temps = self.temp_air(hours)

        def mismatch(td):
            rh = np.minimum(relative_humidity_from_dew_point(temps, td), 100.0)
            return rh.mean() - self.relative_humidity_mean

        return brentq(mismatch, self.temp_min - 40.0, self.temp_max)

    def relative_humidity(self, hour):
        """Relative humidity [%] at local clock hours (constant dew point)."""
        return np.minimum(relative_humidity_from_dew_point(self.temp_air(hour),
                                                           self.dew_point()), 100.0)

    def temp_sea(self, hour):
        """SST [K] with its diurnal cycle peaking at 14:00 local [G]."""
        return sst_diurnal(hour, self.temp_sea_mean, self.sst_amplitude, 14.0)

    def weather(self, step_minutes: int = 60, sst_cycle: bool = True) -> Weather:
        """The design day as a periodic :class:`Weather` record starting 00:00 local.

        Parameters
        ----------
        step_minutes : int
            Time step [min] (divides 1440).
        sst_cycle : bool
            True: the SST with the design day's prescribed diurnal cycle
            (:meth:`temp_sea`); False: its daily mean all day, the bulk temperature at the
            base of the warm layer when a skin model makes the diurnal warming
            (:mod:`.sea_skin`; a prescribed cycle on top would count the warming twice).
        """
        n = int(round(24 * 60 / step_minutes))
        require_ok = 24 * 60 % step_minutes == 0
        if not require_ok:
            raise InputError("step_minutes", step_minutes, "must divide 1440")
        day = pd.Timestamp(self.date).tz_localize(self.tz)
        time = pd.date_range(day, periods=n, freq=f"{step_minutes}min")
        hours = np.arange(n) * step_minutes / 60.0
        return Weather(time=time, temp_air=self.temp_air(hours),
                       relative_humidity=self.relative_humidity(hours),
                       wind_speed=np.full(n, self.wind_speed),
                       wind_direction=np.full(n, self.wind_direction),
                       cloud_cover=np.full(n, self.cloud_cover),
                       temp_sea=(self.temp_sea(hours) if sst_cycle
                                 else np.full(n, self.temp_sea_mean)), periodic=True,
                       source=f"climatology:{self.name}")

    def source_table(self) -> str:
        """Human-readable table of every number, its label and its source."""
        rows = [f"{self.name} ({self.date}, {self.latitude} N {self.longitude} E, {self.tz})"]
        for key, (label, text) in self.sources.items():
            val = getattr(self, key, None)
            if callable(val) or val is None:
                val = ""
            elif isinstance(val, float) and key.startswith("temp") and key != "temp_sea_mean":
                val = f"{val - ZERO_CELSIUS:.2f} degC"
            elif key == "temp_sea_mean":
                val = f"{val - ZERO_CELSIUS:.2f} degC"
            rows.append(f"  {key:24s} {str(val):>14s}  {label:10s} {text}")
        rows.append(f"  {'cloud_cover':24s} {self.cloud_cover:14.3f}  DERIVED    "
                    "1 − sunshine / SPA day length")
        return "\n".join(rows)


_SST_MIN = 2.8 + ZERO_CELSIUS      # [B] SOURCED winter minimum
_SST_MAX = 23.6 + ZERO_CELSIUS     # [B] SOURCED August peak


def dalian_summer() -> ClimateDay:
    """Mid-July design day at Dalian (15 July)."""
    return ClimateDay(
        name="dalian_summer", date=DESIGN_DAY_DATES["summer"], **{k: DALIAN[k] for k in
                                                     ("latitude", "longitude", "altitude", "tz")},
        temp_max=26.0 + ZERO_CELSIUS, temp_min=20.7 + ZERO_CELSIUS,
        temp_mean_source=23.0 + ZERO_CELSIUS,
        relative_humidity_mean=84.0, sunshine_hours=7.4,
        wind_speed=4.0, wind_direction=180.0,
        temp_sea_mean=float(annual_harmonic_sst(7.0, _SST_MIN, _SST_MAX)),
        sst_amplitude=0.15,
        sources={
            "temp_max": ("SOURCED", "[A] July mean daily maximum 26.0 degC"),
            "temp_min": ("SOURCED", "[A] July mean daily minimum 20.7 degC"),
            "temp_mean_source": ("SOURCED", "[A] July mean 23.0 degC (check only)"),
            "relative_humidity_mean": ("SOURCED", "[B] midsummer mean RH 84 %"),
            "sunshine_hours": ("SOURCED", "[C] July mean sunshine 7.4 h/day"),
            "wind_speed": ("ASSUMPTION", "4.0 m/s: no station normal at hand; inside "
                           "the 'force 2-3' (1.6-5.4 m/s) summer mean of a secondary "
                           "source (bkwk.cn, Sina weather statistics)"),
            "wind_direction": ("SOURCED", "[D] southerly monsoon in summer -> 180 deg"),
            "temp_sea_mean": ("DERIVED", "[B]+[F] annual harmonic through 2.8 (Feb) and "
                              "23.6 degC (Aug), at mid-July"),
            "sst_amplitude": ("ASSUMPTION", "[G] 0.15 K half-range (0.3 K range)"),
        })


def dalian_winter() -> ClimateDay:
    """Mid-January design day at Dalian (15 January)."""
    return ClimateDay(
        name="dalian_winter", date=DESIGN_DAY_DATES["winter"], **{k: DALIAN[k] for k in
                                                     ("latitude", "longitude", "altitude", "tz")},
        temp_max=-1.2 + ZERO_CELSIUS, temp_min=-8.2 + ZERO_CELSIUS,
        temp_mean_source=-4.9 + ZERO_CELSIUS,
        relative_humidity_mean=55.0, sunshine_hours=6.8,
        wind_speed=5.0, wind_direction=0.0,
        temp_sea_mean=float(annual_harmonic_sst(1.0, _SST_MIN, _SST_MAX)),
        sst_amplitude=0.05,
        sources={
            "temp_max": ("SOURCED", "[A] January mean daily maximum −1.2 degC"),
            "temp_min": ("SOURCED", "[A] January mean daily minimum −8.2 degC"),
            "temp_mean_source": ("SOURCED", "[A] January mean −4.9 degC (check only)"),
            "relative_humidity_mean": ("SOURCED", "[B] January mean RH 55 %"),
            "sunshine_hours": ("SOURCED", "[C] January mean sunshine 6.8 h/day"),
            "wind_speed": ("ASSUMPTION", "5.0 m/s: no station normal at hand; gale days "
                           "most frequent in winter/spring, fewest in summer ([A] page)"),
            "wind_direction": ("SOURCED", "[D] northerly monsoon in winter -> 0 deg"),
            "temp_sea_mean": ("DERIVED", "[B]+[F] annual harmonic through 2.8 (Feb) and "
                              "23.6 degC (Aug), at mid-January"),
            "sst_amplitude": ("ASSUMPTION", "[G] 0.05 K half-range: weak winter sun, "
                              "strong wind"),
        })


_DAYS = {"summer": dalian_summer, "winter": dalian_winter,
         "dalian_summer": dalian_summer, "dalian_winter": dalian_winter}


def climate_day(name: str) -> ClimateDay:
    """Look up a built-in design day by name ('summer', 'winter', 'dalian_summer', ...)."""
    try:
        return _DAYS[name]()
    except KeyError:
        raise InputError("weather.climatology", name, f"must be one of {sorted(_DAYS)}")
