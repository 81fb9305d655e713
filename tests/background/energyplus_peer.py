"""EnergyPlus as the peer of the land surface-energy solver: the IDF writer, the EPW reader, the
runner and the side-by-side comparison (used by ``test_bg_surface_energyplus.py`` and
``benchmarks/bench_surface_energyplus.py``; EnergyPlus is no runtime dependency).

The EnergyPlus model: per test surface one 10 m × 10 m × 3 m box zone whose roof is the
test surface (outdoors, sun- and wind-exposed, horizontal: it sees the sky only), walls and
floor adiabatic. The zone air is held constant by a huge air heat capacity
(``ZoneCapacitanceMultiplier:ResearchSpecial``), the inside face of the test surface couples
to it through a fixed convective coefficient (``SurfaceProperty:ConvectionCoefficients``,
``Value``) and radiates almost nothing (inner thermal absorptance 1e-4): the inside boundary
is then exactly ``'room'`` of the solver, with the zone air as the room and the fixed
coefficient as the film. A film of 1000 W m-2 K-1 makes it a fixed bottom temperature (the
paving slab). Outside, the matched cases impose ``h = a + b v`` through
``SurfaceConvectionAlgorithm:Outside:UserCurve`` (a ``Curve:Linear`` of the weather-file wind
speed); the default cases keep EnergyPlus's DOE-2 outside convection. Rain and snow flags are
off (EnergyPlus would otherwise pin a wet surface to the wet-bulb temperature).

Weather on the 5-minute steps as EnergyPlus builds it: an EPW value is the value at the end
of its hour and the steps interpolate linearly between the hour values.
"""

from __future__ import annotations

import dataclasses
import os
import tempfile
import time
from pathlib import Path

import numpy as np
import pandas as pd
import pvlib

from imaging.background import surface_energy as se
from imaging.background.physical import land_convection
from imaging.background.surface_classes import SURFACE_CLASSES, Layer

TIMESTEPS_PER_HOUR = 20
ROOF_FILM = SURFACE_CLASSES["building"].room_film_coefficient   # [W m-2 K-1]
FIXED_FILM = 1000.0             # inside coefficient that pins the slab's bottom [W m-2 K-1]
USER_CURVE = (4.0, 4.0)         # h = a + b v, ISO 6946:2017 eq. C.2 [W m-2 K-1], [J m-3 K-1]
INNER_EMISSIVITY = 1.0e-4
SLAB_ALGORITHM = "ConductionFiniteDifference"
"""EnergyPlus's conduction model for the 1 m paving slab: its CTFs for that construction take
a 55-minute time step (the 'Construction CTF' report) and interpolate histories in between;
the finite-difference model steps with the zone's 5 minutes."""

CLIMATES = {"san_francisco": "USA_CA_San.Francisco.Intl.AP.724940_TMY3.epw",
            "phoenix": "USA_AZ_Phoenix-Sky.Harbor.Intl.AP.722780_TMY3.epw",
            "miami": "USA_FL_Miami.Intl.AP.722020_TMY3.epw"}
WEEKS = {"july": (7, 8), "january": (1, 8)}          # month, first day (7 days each)


@dataclasses.dataclass(frozen=True)
class PeerSurface:
    name: str                     # EnergyPlus surface and zone name (upper case)
    layers: tuple                 # Layer, outside first
    solar_absorptance: float
    emissivity: float
    inside_film: float            # [W m-2 K-1]
    user_curve: bool              # True: h = a + b v outside; False: EnergyPlus default


def peer_surfaces() -> tuple:
    land = SURFACE_CLASSES["land"]
    roof = SURFACE_CLASSES["building"]
    out = []
    for user in (True, False):
        tag = "USER" if user else "DEFAULT"
        out.append(PeerSurface(f"SLAB_{tag}", land.layers, 1 - land.albedo, land.emissivity,
                               FIXED_FILM, user))
        out.append(PeerSurface(f"ROOF_{tag}", roof.layers, 1 - roof.albedo, roof.emissivity,
                               ROOF_FILM, user))
    return tuple(out)


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
               13: "ghi", 14: "dni", 15: "dhi", 21: "wind_speed"}


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
    """The weather EnergyPlus uses on its 5-minute steps of ``days`` days from month/day
    00:00 (standard time). Index: the step's end time; row 0 is 00:00 of the first day.

    EnergyPlus's rules, checked against its reported site variables: a state value
    (temperature, humidity, pressure, wind, long-wave) belongs to the end of its hour, a
    solar value (an hour's total) to the middle of its hour, and the steps interpolate
    linearly between them; before the first hour the run continues its warm-up, the first day
    repeated, so the value "before" the first hour is that day's last. The sun (beam) is
    zero while it is below the horizon."""
    first = epw.index[(epw.month == month) & (epw.day == day) & (epw.hour == 1)][0]
    hourly = epw.iloc[first:first + 24 * days].reset_index(drop=True)
    n = 24 * days * TIMESTEPS_PER_HOUR + 1
    x = np.arange(n) / TIMESTEPS_PER_HOUR                                   # hours
    hours = np.arange(1, 24 * days + 1, dtype=float)
    out = {}
    for name in EPW_COLUMNS.values():
        v = hourly[name].to_numpy()
        if name in ("dni", "dhi", "ghi"):
            out[name] = np.interp(x, np.concatenate([[-0.5], hours - 0.5]),
                                  np.concatenate([[v[23]], v]))
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
# IDF
# ------------------------------------------------------------------------------------------
def _obj(kind: str, *fields) -> str:
    body = ",\n  ".join(str(f) for f in fields)
    return f"{kind},\n  {body};\n"


def engine_version() -> str:
    """``major.minor`` of the EnergyPlus engine in the installed wheel (the IDF's Version)."""
    from pyenergyplus.api import EnergyPlusAPI

    v = EnergyPlusAPI().functional.ep_version()
    return f"{v.major}.{v.minor}" if hasattr(v, "major") else ".".join(str(v).split(".")[:2])


def write_idf(path, surfaces=None, weeks=("july", "january"), version: str = "25.2") -> None:
    """The EnergyPlus input for ``surfaces`` (default :func:`peer_surfaces`) over the weeks."""
    surfaces = surfaces or peer_surfaces()
    a, b = USER_CURVE
    parts = [
        _obj("Version", version),
        _obj("SimulationControl", "No", "No", "No", "No", "Yes", "No", 1),
        _obj("Building", "peer", 0, "Country", 0.001, 0.001, "MinimalShadowing", 50, 20),
        _obj("Timestep", TIMESTEPS_PER_HOUR),
        # sun positions every day (the default 20-day reuse shifts January's noon sun by ~1°)
        _obj("ShadowCalculation", "PolygonClipping", "Periodic", 1),
        _obj("HeatBalanceAlgorithm", "ConductionTransferFunction"),
        _obj("SurfaceConvectionAlgorithm:Inside", "TARP"),
        _obj("SurfaceConvectionAlgorithm:Outside", "DOE-2"),
        _obj("GlobalGeometryRules", "UpperLeftCorner", "Counterclockwise", "World"),
        _obj("ZoneCapacitanceMultiplier:ResearchSpecial", "frozen air", "", 1.0e7, 1, 1, 1),
        _obj("Curve:Linear", "user h", a, b, 0.0, 100.0),
        _obj("SurfaceConvectionAlgorithm:Outside:UserCurve", "user curve", "WeatherFile",
             "user h", "", "", ""),
        _obj("OutputControl:Files", "Yes"),
    ]
    for name, (month, day) in WEEKS.items():
        if name in weeks:
            parts.append(_obj("RunPeriod", name, month, day, "", month, day + 6, "", "",
                              "No", "No", "No", "No", "No", "No"))
    # walls and floor: adiabatic, light
    parts.append(_obj("Material", "board", "Smooth", 0.0127, 0.16, 784.9, 830.0, 0.9, 0.5, 0.5))
    parts.append(_obj("Construction", "board", "board"))
    materials = {}
    for s in surfaces:
        names = []
        for i, layer in enumerate(s.layers):
            mname = f"{s.name}_{i}"
            outer, inner = i == 0, i == len(s.layers) - 1
            therm = s.emissivity if outer else (INNER_EMISSIVITY if inner else 0.9)
            solar = s.solar_absorptance if outer else 0.5
            materials[mname] = _obj("Material", mname, "Rough", layer.thickness,
                                    layer.conductivity, layer.density, layer.specific_heat,
                                    therm, solar, solar)
            names.append(mname)
        parts.extend(materials[m] for m in names)
        parts.append(_obj("Construction", s.name, *names))
    for k, s in enumerate(surfaces):
        x0 = 30.0 * k
        z = _obj("Zone", s.name, 0, x0, 0, 0)
        parts.append(z)
        parts.append(_surface(s.name, "Roof", s.name, s.name, "Outdoors", "SunExposed",
                              "WindExposed", [(x0, 10, 3), (x0, 0, 3), (x0 + 10, 0, 3),
                                              (x0 + 10, 10, 3)]))
        walls = {"FLOOR": ("Floor", [(x0 + 10, 10, 0), (x0 + 10, 0, 0), (x0, 0, 0), (x0, 10, 0)]),
                 "S": ("Wall", [(x0, 0, 3), (x0, 0, 0), (x0 + 10, 0, 0), (x0 + 10, 0, 3)]),
                 "E": ("Wall", [(x0 + 10, 0, 3), (x0 + 10, 0, 0), (x0 + 10, 10, 0),
                                (x0 + 10, 10, 3)]),
                 "N": ("Wall", [(x0 + 10, 10, 3), (x0 + 10, 10, 0), (x0, 10, 0), (x0, 10, 3)]),
                 "W": ("Wall", [(x0, 10, 3), (x0, 10, 0), (x0, 0, 0), (x0, 0, 3)])}
        for tag, (kind, verts) in walls.items():
            parts.append(_surface(f"{s.name}_{tag}", kind, "board", s.name, "Adiabatic",
                                  "NoSun", "NoWind", verts))
        conv = ["Inside", "Value", s.inside_film, "", ""]
        if s.user_curve:
            conv = ["Outside", "UserCurve", "", "", "user curve"] + conv
        parts.append(_obj("SurfaceProperty:ConvectionCoefficients", s.name, *conv))
        if s.name.startswith("SLAB") and SLAB_ALGORITHM != "CTF":
            parts.append(_obj("SurfaceProperty:HeatTransferAlgorithm", s.name, SLAB_ALGORITHM))
    for var in OUTPUT_VARIABLES:
        parts.append(_obj("Output:Variable", "*", var, "Timestep"))
    Path(path).write_text("\n".join(parts), encoding="ascii")


def _surface(name, kind, construction, zone, boundary, sun, wind, verts) -> str:
    coords = [c for v in verts for c in v]
    return _obj("BuildingSurface:Detailed", name, kind, construction, zone, "", boundary, "",
                sun, wind, "autocalculate", len(verts), *coords)


OUTPUT_VARIABLES = (
    "Surface Outside Face Temperature",
    "Surface Inside Face Temperature",
    "Surface Outside Face Convection Heat Transfer Coefficient",
    "Surface Outside Face Convection Heat Gain Rate per Area",
    "Surface Outside Face Net Thermal Radiation Heat Gain Rate per Area",
    "Surface Outside Face Solar Radiation Heat Gain Rate per Area",
    "Surface Outside Face Conduction Heat Transfer Rate per Area",
    "Surface Outside Face Incident Solar Radiation Rate per Area",
    "Zone Mean Air Temperature",
    "Site Outdoor Air Drybulb Temperature",
    "Site Wind Speed",
    "Site Direct Solar Radiation Rate per Area",
    "Site Diffuse Solar Radiation Rate per Area",
    "Site Horizontal Infrared Radiation Rate per Area",
    "Site Solar Azimuth Angle",
    "Site Solar Altitude Angle",
)


# ------------------------------------------------------------------------------------------
# Runs
# ------------------------------------------------------------------------------------------
def run_energyplus(climate: str, weeks=("july", "january"), workdir=None) -> tuple:
    """Run EnergyPlus on a climate's TMY3 file; returns (outputs DataFrame with one row per
    5-minute step of every week, wall time [s])."""
    from pyenergyplus.api import EnergyPlusAPI

    workdir = Path(workdir or tempfile.mkdtemp(prefix="eplus_"))
    idf = workdir / "peer.idf"
    write_idf(idf, weeks=weeks, version=engine_version())
    api = EnergyPlusAPI()
    state = api.state_manager.new_state()
    api.runtime.set_console_output_status(state, False)
    t0 = time.perf_counter()
    code = api.runtime.run_energyplus(state, ["-w", str(weather_file(climate)), "-d",
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


@dataclasses.dataclass
class CaseResult:
    climate: str
    week: str
    surface: str
    eplus: dict          # name → (n,) arrays on the 5-minute steps (end of step)
    ours: dict
    wall_ours: float     # [s] our solver's wall time, the call's share of this surface


EPLUS_TERMS = ("Temperature", "Convection Heat Transfer Coefficient",
               "Convection Heat Gain Rate per Area",
               "Net Thermal Radiation Heat Gain Rate per Area",
               "Solar Radiation Heat Gain Rate per Area",
               "Conduction Heat Transfer Rate per Area",
               "Incident Solar Radiation Rate per Area")


def per_column_convection(user_curve: np.ndarray, default=None):
    """``h = a + b v`` on the columns that had EnergyPlus's user curve, ``default`` (the
    project's flat-plate correlation when None; arrays of the other columns only) on the
    others."""
    user = np.asarray(user_curve, dtype=bool)
    linear = se.convection_linear(*USER_CURVE)
    default = default or se.convection_correlation()

    def h(temp_surface, temp_air, wind_speed):
        out = np.empty(np.shape(temp_surface))
        ts, ta, v = (np.broadcast_to(x, out.shape) for x in (temp_surface, temp_air,
                                                             wind_speed))
        out[user] = linear(ts[user], ta[user], v[user])
        out[~user] = default(ts[~user], ta[~user], v[~user])
        return out

    return h


def compare(climate: str, df: pd.DataFrame, weeks=("july", "january"),
            h_from_eplus: bool = False, sun_shift_minutes: float = 0.0,
            scheme: str = "backward_euler", substeps: int = 1) -> list:
    """Our solver on the peer surfaces (the four as four columns of one call per week) with
    the weather EnergyPlus used.

    Convection: ``h = a + b v`` where EnergyPlus had the user curve, our default correlation
    where it had DOE-2; with ``h_from_eplus`` EnergyPlus's reported h of every step instead
    (the convection term made equal)."""
    epw, loc = read_epw(weather_file(climate))
    months = df["Date/Time"].str.strip().str.slice(0, 2).astype(int).to_numpy()
    surfaces = peer_surfaces()
    classes = {s.name.lower(): _peer_class(s) for s in surfaces}
    out = []
    for week in weeks:
        month, day = WEEKS[week]
        rows = np.nonzero(months == month)[0]
        wx = forcing_on_steps(epw, loc, month, day, 7)
        zen, _ = sun_position(wx.index, loc, sun_shift_minutes)
        cosz = np.clip(np.cos(np.radians(zen)), 0.0, None)
        incident = wx["dni"].to_numpy() * cosz + wx["dhi"].to_numpy()
        eplus = [{v: eplus_column(df, s.name, f"Surface Outside Face {v}")[rows]
                  for v in EPLUS_TERMS} for s in surfaces]
        room = [np.mean(eplus_column(df, s.name, "Zone Mean Air Temperature")[rows]) + 273.15
                for s in surfaces]
        cols = se.build_columns(list(classes), room, classes=classes)
        n_t = len(wx)
        absorptance = np.array([s.solar_absorptance for s in surfaces])
        wind = np.repeat(wx["wind_speed"].to_numpy()[:, None], len(surfaces), axis=1)
        # our default: the port background's own (the surface layer's log law with
        # stability, imaging.background.physical.land_convection)
        conv = per_column_convection([s.user_curve for s in surfaces], default=land_convection(
            [classes[s.name.lower()] for s in surfaces if not s.user_curve],
            float(np.mean(wx["pressure"]))))
        if h_from_eplus:
            # the wind input carries EnergyPlus's h of each step and h = 0 + 1·"wind" replays
            # it (row 0, 00:00, takes the first step's value)
            h_ep = np.stack([e["Convection Heat Transfer Coefficient"] for e in eplus], axis=1)
            wind = np.concatenate([h_ep[:1], h_ep])
            conv = se.convection_linear(0.0, 1.0)
        forcing = se.SurfaceForcing(
            3600.0 / TIMESTEPS_PER_HOUR, incident[:, None] * absorptance,
            np.repeat(wx["longwave_down"].to_numpy()[:, None], len(surfaces), axis=1),
            wx["temp_air"].to_numpy(), wx["relative_humidity"].to_numpy(), wind,
            wx["pressure"].to_numpy())
        t0 = time.perf_counter()
        res = se.solve_surface_energy(forcing, cols, convection=conv, scheme=scheme,
                                      substeps=substeps)
        wall = time.perf_counter() - t0
        for j, s in enumerate(surfaces):
            ours = {"Temperature": res.temp_surface[1:, j] - 273.15,
                    "Convection Heat Transfer Coefficient": res.h_convection[1:, j],
                    "Convection Heat Gain Rate per Area": -res.sensible[1:, j],
                    "Net Thermal Radiation Heat Gain Rate per Area": res.longwave_net[1:, j],
                    "Solar Radiation Heat Gain Rate per Area": res.shortwave_net[1:, j],
                    # EnergyPlus: conduction heat gain of the outer face (= −G)
                    "Conduction Heat Transfer Rate per Area": -res.ground[1:, j],
                    "Incident Solar Radiation Rate per Area": incident[1:]}
            out.append(CaseResult(climate, week, s.name, eplus[j], ours, wall / len(surfaces)))
    return out


def _peer_class(s: PeerSurface):
    base = SURFACE_CLASSES["land" if s.name.startswith("SLAB") else "building"]
    return dataclasses.replace(base, name=s.name.lower(), bottom="room",
                               room_film_coefficient=s.inside_film, albedo=1 - s.solar_absorptance,
                               emissivity=s.emissivity, layers=tuple(s.layers))


def statistics(case: CaseResult, skip_days: int = 1) -> dict:
    """RMS and max |difference| of the hourly outer surface temperature (days after
    ``skip_days``), and each flux term at local noon of the last day."""
    k = TIMESTEPS_PER_HOUR
    start = skip_days * 24 * k
    hourly = slice(start + k - 1, None, k)             # the steps ending on the hour
    d = case.ours["Temperature"][hourly] - case.eplus["Temperature"][hourly]
    noon = len(case.ours["Temperature"]) - 12 * k - 1
    terms = {v: (case.ours[v][noon], case.eplus[v][noon]) for v in case.ours}
    return {"rms": float(np.sqrt(np.mean(d ** 2))), "max": float(np.max(np.abs(d))),
            "noon": terms}
