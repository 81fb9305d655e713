"""EnergyPlus as a peer: what every comparison shares (used by the land columns'
``background/energyplus_land.py``, the ship boundary's ``boundary/energyplus_ship.py`` and
their benchmarks; EnergyPlus is no runtime dependency).

* the TMY3 weather files shipped with the ``pyenergyplus-lbnl`` wheel and EnergyPlus's own
  reading of them on its sub-hourly steps (:func:`read_epw`, :func:`forcing_on_steps`);
* the sun at those steps (pvlib's SPA, :func:`sun_position`);
* IDF text (:func:`idf_object`), the engine's version, a run (:func:`run_energyplus`) and its
  CSV columns (:func:`eplus_column`);
* the side-by-side statistics of a case (:func:`statistics`).

Weather on the steps as EnergyPlus builds it: an EPW state value (temperature, humidity,
pressure, wind, long-wave) is the value at the end of its hour, a solar value (an hour's
total) belongs to the middle of its hour, and the steps interpolate linearly between them.
"""

from __future__ import annotations

import dataclasses
import tempfile
import time
from pathlib import Path

import numpy as np
import pandas as pd
import pvlib

TIMESTEPS_PER_HOUR = 20

CLIMATES = {"san_francisco": "USA_CA_San.Francisco.Intl.AP.724940_TMY3.epw",
            "phoenix": "USA_AZ_Phoenix-Sky.Harbor.Intl.AP.722780_TMY3.epw",
            "miami": "USA_FL_Miami.Intl.AP.722020_TMY3.epw"}
WEEKS = {"july": (7, 8), "january": (1, 8)}          # month, first day (7 days each)


#: Output variables of every surface that both peers read: temperatures and each term of the
#: outer face's balance [EnergyPlus's names]
SURFACE_OUTPUTS = (
    "Surface Outside Face Temperature",
    "Surface Inside Face Temperature",
    "Surface Outside Face Convection Heat Transfer Coefficient",
    "Surface Outside Face Convection Heat Gain Rate per Area",
    "Surface Outside Face Net Thermal Radiation Heat Gain Rate per Area",
    "Surface Outside Face Solar Radiation Heat Gain Rate per Area",
    "Surface Outside Face Conduction Heat Transfer Rate per Area",
    "Surface Outside Face Incident Solar Radiation Rate per Area",
)

#: The zone's and the site's output variables both peers read
SITE_OUTPUTS = (
    "Zone Mean Air Temperature",
    "Site Outdoor Air Drybulb Temperature",
    "Site Wind Speed",
    "Site Direct Solar Radiation Rate per Area",
    "Site Diffuse Solar Radiation Rate per Area",
    "Site Horizontal Infrared Radiation Rate per Area",
    "Site Solar Azimuth Angle",
    "Site Solar Altitude Angle",
)

#: Noon terms the benchmarks print: (EnergyPlus's "Surface Outside Face ..." suffix, label)
NOON_TERMS = (("Temperature", "T_s [C]"),
              ("Convection Heat Transfer Coefficient", "h"),
              ("Solar Radiation Heat Gain Rate per Area", "SW abs"),
              ("Net Thermal Radiation Heat Gain Rate per Area", "LW net"),
              ("Convection Heat Gain Rate per Area", "conv"),
              ("Conduction Heat Transfer Rate per Area", "cond"))


def energyplus_available() -> bool:
    try:
        import pyenergyplus.api  # noqa: F401
    except ImportError:
        return False
    return True


def weather_file(climate: str) -> Path:
    from pyenergyplus import dataset

    return Path(dataset.weatherdir) / CLIMATES[climate]


# ------------------------------------------------------------------------------------------
# EPW
# ------------------------------------------------------------------------------------------
EPW_COLUMNS = {6: "temp_air", 8: "relative_humidity", 9: "pressure", 12: "longwave_down",
               13: "ghi", 14: "dni", 15: "dhi", 20: "wind_direction", 21: "wind_speed"}
SOLAR_COLUMNS = ("dni", "dhi", "ghi")


def read_epw(path) -> tuple[pd.DataFrame, dict]:
    """Hourly EPW fields (°C → K, the rest SI) indexed by month, day, hour (1–24: the hour
    ending at that time), and the location header."""
    lines = Path(path).read_text(encoding="latin-1").splitlines()
    head = lines[0].split(",")
    loc = {"latitude": float(head[6]), "longitude": float(head[7]), "tz": float(head[8]),
           "altitude": float(head[9])}
    rows = [line.split(",") for line in lines[8:] if line.strip()]
    data = {"month": [int(r[1]) for r in rows], "day": [int(r[2]) for r in rows],
            "hour": [int(r[3]) for r in rows]}
    for col, name in EPW_COLUMNS.items():
        data[name] = [float(r[col]) for r in rows]
    df = pd.DataFrame(data)
    df["temp_air"] += 273.15
    return df, loc


def forcing_on_steps(epw: pd.DataFrame, loc: dict, month: int, day: int, days: int,
                     year: int = 2023) -> pd.DataFrame:
    """The weather EnergyPlus uses on its steps of ``days`` days from month/day 00:00
    (standard time). Index: the step's end time; row 0 is 00:00 of the first day.

    EnergyPlus's rules, checked against its reported site variables: a state value
    (temperature, humidity, pressure, wind, long-wave) belongs to the end of its hour, a
    solar value (an hour's total) to the middle of its hour, and the steps interpolate
    linearly between them; before the first hour the run continues its warm-up, the first day
    repeated, so the value "before" the first hour is that day's last. The sun (beam) is
    zero while it is below the horizon. The wind direction is the hour's (not interpolated:
    use EnergyPlus's reported surface wind direction where it matters)."""
    first = epw.index[(epw.month == month) & (epw.day == day) & (epw.hour == 1)][0]
    hourly = epw.iloc[first:first + 24 * days].reset_index(drop=True)
    n = 24 * days * TIMESTEPS_PER_HOUR + 1
    x = np.arange(n) / TIMESTEPS_PER_HOUR                                   # hours
    hours = np.arange(1, 24 * days + 1, dtype=float)
    out = {}
    for name in EPW_COLUMNS.values():
        v = hourly[name].to_numpy()
        if name in SOLAR_COLUMNS:
            out[name] = np.interp(x, np.concatenate([[-0.5], hours - 0.5]),
                                  np.concatenate([[v[23]], v]))
        elif name == "wind_direction":
            out[name] = v[np.clip(np.ceil(x).astype(int) - 1, 0, len(v) - 1)]
        else:
            out[name] = np.interp(x, np.concatenate([[0.0], hours]), np.concatenate([[v[23]], v]))
    tz = f"Etc/GMT{-int(loc['tz']):+d}"
    start = pd.Timestamp(year=year, month=month, day=day, tz=tz)
    index = start + pd.to_timedelta(x, unit="h")
    return pd.DataFrame(out, index=index)


def sun_position(index: pd.DatetimeIndex, loc: dict, shift_minutes: float = 0.0):
    """Apparent zenith and azimuth [deg] (pvlib SPA) at the step times shifted by
    ``shift_minutes`` (EnergyPlus computes its sun once per step)."""
    sp = pvlib.solarposition.get_solarposition(index + pd.Timedelta(minutes=shift_minutes),
                                               loc["latitude"], loc["longitude"],
                                               altitude=loc["altitude"])
    return sp["zenith"].to_numpy(), sp["azimuth"].to_numpy()


# ------------------------------------------------------------------------------------------
# IDF and runs
# ------------------------------------------------------------------------------------------
def idf_object(kind: str, *fields) -> str:
    """One IDF object as text."""
    body = ",\n  ".join(str(f) for f in fields)
    return f"{kind},\n  {body};\n"


def idf_surface(name, kind, construction, zone, boundary, sun, wind, verts) -> str:
    """A ``BuildingSurface:Detailed`` (vertices counter-clockwise seen from outside)."""
    coords = [c for v in verts for c in v]
    return idf_object("BuildingSurface:Detailed", name, kind, construction, zone, "", boundary,
                      "", sun, wind, "autocalculate", len(verts), *coords)


def engine_version() -> str:
    """``major.minor`` of the EnergyPlus engine in the installed wheel (the IDF's Version)."""
    from pyenergyplus.api import EnergyPlusAPI

    v = EnergyPlusAPI().functional.ep_version()
    return f"{v.major}.{v.minor}" if hasattr(v, "major") else ".".join(str(v).split(".")[:2])


def run_energyplus_idf(write, climate: str, workdir=None, epw=None) -> tuple:
    """Run EnergyPlus on an IDF written by ``write(path, version)`` with a climate's TMY3
    file (or the EPW file ``epw``); returns (outputs DataFrame, wall time [s], work
    folder)."""
    from pyenergyplus.api import EnergyPlusAPI

    workdir = Path(workdir or tempfile.mkdtemp(prefix="eplus_"))
    workdir.mkdir(parents=True, exist_ok=True)
    idf = workdir / "peer.idf"
    write(idf, engine_version())
    api = EnergyPlusAPI()
    state = api.state_manager.new_state()
    api.runtime.set_console_output_status(state, False)
    t0 = time.perf_counter()
    code = api.runtime.run_energyplus(state, ["-w", str(epw or weather_file(climate)), "-d",
                                              str(workdir), str(idf)])
    wall = time.perf_counter() - t0
    api.state_manager.delete_state(state)
    if code != 0:
        err = (workdir / "eplusout.err").read_text(errors="replace")
        raise RuntimeError(f"EnergyPlus failed ({code}):\n{err[-3000:]}")
    df = pd.read_csv(workdir / "eplusout.csv")
    df.columns = [c.strip() for c in df.columns]
    return df, wall, workdir


def eplus_column(df: pd.DataFrame, key: str, variable: str) -> np.ndarray:
    matches = [c for c in df.columns if c.startswith(f"{key}:{variable} [")]
    if not matches:
        raise KeyError(f"{key}:{variable}")
    return df[matches[0]].to_numpy(dtype=float)


def site(df: pd.DataFrame, variable: str, rows=slice(None)) -> np.ndarray:
    """An ``Environment:`` (site) variable of the run."""
    col = [c for c in df.columns if c.startswith(f"Environment:{variable} [")][0]
    return df[col].to_numpy()[rows]


def week_rows(df: pd.DataFrame, month: int) -> np.ndarray:
    """Rows of the run's output that belong to the week of ``month``."""
    months = df["Date/Time"].str.strip().str.slice(0, 2).astype(int).to_numpy()
    return np.nonzero(months == month)[0]


# ------------------------------------------------------------------------------------------
# Statistics
# ------------------------------------------------------------------------------------------
@dataclasses.dataclass
class CaseResult:
    climate: str
    week: str
    surface: str
    eplus: dict          # name → (n,) arrays on the steps (end of step)
    ours: dict
    wall_ours: float     # [s] our solver's wall time, the call's share of this surface


def statistics(case: CaseResult, skip_days: int = 1, noon_day: int = -1) -> dict:
    """RMS and max |difference| of the hourly outer surface temperature (days after
    ``skip_days``), and each term ``(ours, EnergyPlus)`` at local noon of the last day
    (``noon_day``: days counted from the end)."""
    k = TIMESTEPS_PER_HOUR
    start = skip_days * 24 * k
    hourly = slice(start + k - 1, None, k)             # the steps ending on the hour
    d = case.ours["Temperature"][hourly] - case.eplus["Temperature"][hourly]
    noon = len(case.ours["Temperature"]) + (noon_day + 1) * 24 * k - 12 * k - 1
    terms = {v: (case.ours[v][noon], case.eplus[v][noon]) for v in case.ours
             if v in case.eplus}
    return {"rms": float(np.sqrt(np.mean(d ** 2))), "max": float(np.max(np.abs(d))),
            "noon": terms}
