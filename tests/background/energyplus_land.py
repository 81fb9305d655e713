"""EnergyPlus as the peer of the land surface-energy solver: the IDF writer and the side-by-side
comparison (used by ``test_bg_surface_energyplus.py`` and
``benchmarks/bench_surface_energyplus.py``; the weather reading, runs and statistics are the
shared ``tests/energyplus_peer.py``; EnergyPlus is no runtime dependency).

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

Weather on the steps as EnergyPlus builds it: :func:`energyplus_peer.forcing_on_steps`.
"""

from __future__ import annotations

import dataclasses
import time
from pathlib import Path

import numpy as np
import pandas as pd

from energyplus_peer import (CLIMATES, TIMESTEPS_PER_HOUR, WEEKS, CaseResult,  # noqa: F401
                             eplus_column, energyplus_available, engine_version,
                             forcing_on_steps, read_epw, run_energyplus_idf, statistics,
                             sun_position, weather_file)
from energyplus_peer import SITE_OUTPUTS, SURFACE_OUTPUTS
from energyplus_peer import idf_object as _obj
from energyplus_peer import idf_surface as _surface
from imaging.background import surface_energy as se
from imaging.background.physical import land_convection
from imaging.background.surface_classes import SURFACE_CLASSES, Layer

ROOF_FILM = SURFACE_CLASSES["building"].room_film_coefficient   # [W m-2 K-1]
FIXED_FILM = 1000.0             # inside coefficient that pins the slab's bottom [W m-2 K-1]
USER_CURVE = (4.0, 4.0)         # h = a + b v, ISO 6946:2017 eq. C.2 [W m-2 K-1], [J m-3 K-1]
INNER_EMISSIVITY = 1.0e-4
SLAB_ALGORITHM = "ConductionFiniteDifference"
"""EnergyPlus's conduction model for the 1 m paving slab: its CTFs for that construction take
a 55-minute time step (the 'Construction CTF' report) and interpolate histories in between;
the finite-difference model steps with the zone's 5 minutes."""


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


# ------------------------------------------------------------------------------------------
# IDF
# ------------------------------------------------------------------------------------------
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


OUTPUT_VARIABLES = SURFACE_OUTPUTS + SITE_OUTPUTS


# ------------------------------------------------------------------------------------------
# Runs
# ------------------------------------------------------------------------------------------
def run_energyplus(climate: str, weeks=("july", "january"), workdir=None) -> tuple:
    """Run EnergyPlus on a climate's TMY3 file; returns (outputs DataFrame with one row per
    step of every week, wall time [s], work folder)."""
    return run_energyplus_idf(lambda path, version: write_idf(path, weeks=weeks,
                                                              version=version),
                              climate, workdir)


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
