"""The paper's deck reference moments with EnergyPlus on the same day and conditions.

The paper's reference [26] gives the deck's area-mean temperature at four moments (summer
12:00 and 07:00, winter 12:00 and 08:00; :data:`shipthermal.app.paper.REFERENCE_DECK`);
its conditions are unknown beyond the site and season. Ours are the built-in scenario's:
the Dalian design day of the season (clear-sky irradiance through the day's cloud, the
sky model's long-wave, the climatology's air, humidity and wind), the deck's 3 mm epoxy
non-skid covering on 10 mm steel, α 0.85, ε 0.95, the ISO 7547 compartment below.

The same day for EnergyPlus: an EPW whose every day of the summer half-year is the summer
design day and every other day the winter one, each hour holding what our environment gives
(the state values at the hour's end, the irradiance as the hour's mean, long-wave as ours),
so both codes see the same weather; a 20 m deck plate whose inside face meets the
compartment air through a fixed film (ISO 6946's downward convection 0.7 plus ε h_r0: the
film of a hot deck over a cooler room, the case of every reference moment but winter
08:00), DOE-2 outside. The compartment is EnergyPlus's frozen zone air (23 °C, its initial
value; ISO 7547's 27 °C in summer and 22 °C in winter would move a deck by about
film / (film + outside coefficients) ≈ 0.2 of the difference). On our side the same plate
(:mod:`energyplus_ship`) with that compartment: with DOE-2 and EnergyPlus's sky
(``matched``) and with our default convection on the frigate's deck box (``default``); the
whole ship's answer is ``validate``'s.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np

import energyplus_ship as es
from energyplus_peer import WEEKS, statistics, weather_file
from shipthermal.app.paper import REFERENCE_DECK
from shipthermal.geometry.layups import DECK_LAYUP
from shipthermal.parameters import LONGWAVE_EMISSIVITY, SOLAR_ABSORPTIVITY
from shipthermal.units import ZERO_CELSIUS

PAPER_DECK = es.Plate("PAPER_DECK", 0.0, 0.0, 20.0, 20.0, DECK_LAYUP, SOLAR_ABSORPTIVITY["deck"],
                      LONGWAVE_EMISSIVITY["deck"], "deck", (132.0, 15.0, 0.5))
"""The built-in frigate's deck as a plate: its layup and optics, and (for our default's
flow length) the frigate's deck box, 132 m by 15 m."""

MOMENTS = {("summer", 12.0): "july", ("summer", 7.0): "july", ("winter", 12.0): "january",
           ("winter", 8.0): "january"}


def design_day_epw(path) -> Path:
    """An EPW of the built-in design days (summer from April to September, winter otherwise),
    on the San Francisco TMY3 file's layout with Dalian's header."""
    from shipthermal.app.scenario import default_scenario

    days = {}
    for season in ("summer", "winter"):
        env = default_scenario(season).environment()
        fine = env.at(np.arange(0.0, 86400.0 + 1.0, 60.0))
        hour_end = env.at(np.arange(3600.0, 86400.0 + 1.0, 3600.0))

        def hourly(x):
            x = np.asarray(x, dtype=float)
            return np.array([np.mean(0.5 * (x[60 * k:60 * k + 60] + x[60 * k + 1:60 * k + 61]))
                             for k in range(24)])

        days[season] = {
            "temp_air": hour_end.temp_air - ZERO_CELSIUS,
            "rh": hour_end.relative_humidity,
            "dew": _dew_point_c(hour_end.temp_air, hour_end.relative_humidity),
            "ir": hour_end.longwave_down, "ghi": hourly(fine.ghi), "dni": hourly(fine.dni),
            "dhi": hourly(fine.dhi), "wdir": hour_end.wind_direction,
            "wind": hour_end.wind_speed, "cloud": np.round(10.0 * hour_end.cloud_cover)}
    lines = Path(weather_file("san_francisco")).read_text(encoding="latin-1").splitlines()
    head = lines[0].split(",")
    head[1:10] = ["Dalian", "LN", "CHN", "built-in design days", "546620", "38.91", "121.63",
                  "8.0", "92.0"]
    out = [",".join(head)] + lines[1:8]
    for line in lines[8:]:
        f = line.split(",")
        month, hour = int(f[1]), int(f[3])
        d = days["summer" if 4 <= month <= 9 else "winter"]
        k = hour - 1
        f[6], f[7], f[8] = f"{d['temp_air'][k]:.2f}", f"{d['dew'][k]:.2f}", f"{d['rh'][k]:.1f}"
        f[9] = "101325"
        f[12], f[13], f[14], f[15] = (f"{d['ir'][k]:.2f}", f"{d['ghi'][k]:.2f}",
                                      f"{d['dni'][k]:.2f}", f"{d['dhi'][k]:.2f}")
        f[20], f[21] = f"{d['wdir'][k]:.1f}", f"{d['wind'][k]:.2f}"
        f[22] = f[23] = f"{int(d['cloud'][k])}"
        out.append(",".join(f))
    Path(path).write_text("\n".join(out) + "\n", encoding="latin-1")
    return Path(path)


def _dew_point_c(temp_air, rh):
    from shipthermal.environment.sky import dew_point

    return dew_point(temp_air, np.maximum(rh, 0.1)) - ZERO_CELSIUS


def reference_table(workdir) -> list:
    """The four moments: the paper's value, EnergyPlus's deck, our plate (matched, default),
    all on the last day of a week of the repeated design day [K]."""
    workdir = Path(workdir)
    workdir.mkdir(parents=True, exist_ok=True)
    epw = design_day_epw(workdir / "dalian_design_days.epw")
    plates = (PAPER_DECK,)
    df, _, _ = es.run_energyplus("dalian", workdir=workdir / "eplus", plates=plates, epw=epw)
    res = {}
    for week in WEEKS:
        wk = es.week_inputs("dalian", df, week, plates, epw)
        ours, _ = es.run_ours(wk, ("default", "matched"), plates)
        res[week] = (wk, ours)
    rows = []
    for (season, hour), week in MOMENTS.items():
        wk, ours = res[week]
        k = len(wk.times) - 1 - int(round((24.0 - hour) * 3600.0 / es.TIME_STEP))
        ep = wk.eplus[PAPER_DECK.name]["Temperature"][k - 1] + ZERO_CELSIUS
        rows.append({"season": season, "time": f"{int(hour):02d}:00",
                     "reference_K": REFERENCE_DECK[(season, hour)], "energyplus_K": ep,
                     "ours_matched_K": ours[("matched", PAPER_DECK.name)]["Temperature"][k - 1]
                     + ZERO_CELSIUS,
                     "ours_default_K": ours[("default", PAPER_DECK.name)]["Temperature"][k - 1]
                     + ZERO_CELSIUS,
                     "air_K": wk.weather["temp_air"].to_numpy()[k],
                     "room_K": wk.room[PAPER_DECK.name],
                     "matched_rms_K": statistics(_case(wk, ours, "matched"))["rms"]})
    return rows


def _case(wk, ours, step):
    from energyplus_peer import CaseResult

    ev = {k: wk.eplus[PAPER_DECK.name][k] for k in es.TERMS}
    return CaseResult("dalian", "", PAPER_DECK.name, ev, ours[(step, PAPER_DECK.name)], 0.0)
