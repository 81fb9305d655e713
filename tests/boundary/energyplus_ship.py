"""EnergyPlus as the peer of the ship's boundary: plates of every orientation, the same
weather, each exchange term side by side (used by ``test_boundary_energyplus.py`` and
``benchmarks/bench_boundary_energyplus.py``; the weather reading, runs and statistics are
the shared ``tests/energyplus_peer.py``; EnergyPlus is no runtime dependency).

The plates (:data:`PLATES`): a 20 m × 20 m horizontal deck (0.3 mm paint on 8 mm steel,
α 0.9, ε 0.95), four 10 m × 3 m walls facing N, E, S and W and a 10 m × 10 m plate tilted
45° to the south (paint on 8 mm steel, α 0.7, ε 0.88), and a west-facing insulated bulkhead
(paint, 6 mm steel, 50 mm mineral wool) with a compartment behind it. Every plate's centroid
is 10 m above the ground, the height of the weather file's wind and of EnergyPlus's
"Country" wind profile's reference, so that the local wind is the file's.

The EnergyPlus model: per plate one box zone (the plate extruded inwards), the plate its
only outdoor surface, the other faces adiabatic. The zone air is held constant by a huge
air heat capacity (``ZoneCapacitanceMultiplier:ResearchSpecial``); the inside face couples
to it through a fixed coefficient (``SurfaceProperty:ConvectionCoefficients``) and radiates
nothing (inner thermal absorptance 1e-4): 0.1 W m-2 K-1 for the plates that are adiabatic
inside, ISO 6946's film with its radiative part for the bulkhead (``BULKHEAD``);
``BULKHEAD_TARP`` keeps EnergyPlus's own inside convection (TARP) and radiation to the zone's
other faces. Outside: DOE-2 convection (EnergyPlus's default), the Perez sky, the ground at
the air temperature reflecting 0.2 of the sun, the EPW's horizontal infrared as the sky.
Rain and snow flags are off.

Our side is the solver (:mod:`shipthermal.model`, :mod:`shipthermal.simulation`) on one
shell graph holding every plate (each plate two triangles through its layup), each outer
face a :class:`~shipthermal.conditions.SurfaceBalance` built from the same weather:

* ``matched``: DOE-2 through :data:`shipthermal.environment.convection.CONVECTION_MODELS`
  (its law evaluated at the solved temperature) with EnergyPlus's surface wind and
  direction, the Perez sky (pvlib), the ground as EnergyPlus has it (at the air temperature,
  albedo 0.2), the same long-wave split (EnergyPlus Engineering Reference, "Outside Surface
  Heat Balance": sky ``F_sky β``, air ``F_sky (1 − β)``, ground ``F_gnd``);
* ``default``: the ship forcing's own choices for a lone plate: the default convection model
  at the file's wind over the part's box, the isotropic sky through ``F_sky``, the sea below
  (``F_sea``: the sea's reflected sun and long-wave, :mod:`shipthermal.environment.sea`,
  the sea at the week's mean air temperature: ASSUMPTION, EPW files carry no sea
  temperature), ISO 6946 inside the bulkhead;
* the steps between them (:data:`STEPS`) attribute the difference term by term.
"""

from __future__ import annotations

import dataclasses
import time

import numpy as np
import pandas as pd
import pvlib

from energyplus_peer import SITE_OUTPUTS, SURFACE_OUTPUTS
from energyplus_peer import (TIMESTEPS_PER_HOUR, WEEKS, CaseResult, eplus_column,
                             forcing_on_steps, idf_object, idf_surface, read_epw,
                             run_energyplus_idf, sun_position, weather_file, week_rows)
from shipthermal.conditions import ConvectionLaw, SurfaceBalance, law_h
from shipthermal import optics
from shipthermal.environment import convection as conv
from shipthermal.environment import sea
from shipthermal.materials import MATERIALS, Layer, Layup, Material
from shipthermal.mesh import build_shell_graph
from shipthermal.model import ThermalModel
from shipthermal.parameters import DEFAULT_CONVECTION_MODEL
from shipthermal.simulation import Simulation
from shipthermal.units import SIGMA

CLIMATES = ("san_francisco", "miami")
"""Two port climates of the wheel's TMY3 files (cool Pacific coast, humid subtropical)."""

CENTROID_HEIGHT = 10.0       # [m] every plate's centroid (the file's wind height)
GROUND_REFLECTANCE = 0.2     # EnergyPlus's default Site:GroundReflectance [-]
ADIABATIC_FILM = 0.1         # [W m-2 K-1] inside film of the plates adiabatic inside
INNER_ABSORPTANCE = 1.0e-4   # the inside faces radiate (almost) nothing
ROUGHNESS = "Smooth"         # EnergyPlus roughness of the painted plates (R_f 1.11)
TIME_STEP = 3600.0 / TIMESTEPS_PER_HOUR
BULKHEAD_ROOM_FILM = 2.5 + 0.9 * 4.0 * SIGMA * 295.0 ** 3
"""ISO 6946 Annex C inside film of a wall, convective 2.5 plus ε h_r0 with ε 0.9 at 295 K
(the film of the forcing's back side) [W m-2 K-1]; fixed in both codes (``matched``)."""

DECK_FILM = 0.7 + 0.9 * 4.0 * SIGMA * 300.0 ** 3
"""ISO 6946 Annex C film of a deck's underside with heat flowing down (0.7 convective) plus
ε h_r0 (ε 0.9 at 300 K) [W m-2 K-1]: a sun-heated deck over a cooler compartment."""

INSIDE_FILMS = {"adiabatic": ADIABATIC_FILM, "room": BULKHEAD_ROOM_FILM, "deck": DECK_FILM}
"""Fixed inside films by the plates' ``inside`` (``'tarp'``: EnergyPlus's own) [W m-2 K-1]."""

STEEL = Material("test_plate", 7850.0, 470.0, 50.0, "the issue's test plate: k 50, c 470")
PAINT = MATERIALS["marine_paint"]
WOOL = MATERIALS["mineral_wool"]


@dataclasses.dataclass(frozen=True)
class Plate:
    """A test plate: orientation, size, layup and optics, and the box of the ship part it
    stands for (the default model's flow lengths)."""

    name: str
    tilt: float               # [deg] from horizontal
    azimuth: float            # [deg] of the outward normal, clockwise from north
    width: float              # [m] horizontal extent
    height: float             # [m] extent along the slope
    layup: Layup
    alpha: float
    epsilon: float
    inside: str               # a key of INSIDE_FILMS (fixed film) | 'tarp' (EnergyPlus's own)
    box: tuple                # (east, north, up) extent of the part's box [m]

    @property
    def normal(self) -> np.ndarray:
        t, a = np.radians(self.tilt), np.radians(self.azimuth)
        return np.array([np.sin(t) * np.sin(a), np.sin(t) * np.cos(a), np.cos(t)])


def _layup(*layers, name):
    return Layup(tuple(layers), name=name)


DECK_LAYUP = _layup(Layer(PAINT, 0.3e-3, 1), Layer(STEEL, 0.008, 2), name="deck")
WALL_LAYUP = DECK_LAYUP
BULKHEAD_LAYUP = _layup(Layer(PAINT, 0.3e-3, 1), Layer(STEEL, 0.006, 1), Layer(WOOL, 0.05, 8),
                        name="bulkhead")
HOUSE = (10.0, 10.0, 3.0)      # the deckhouse a wall belongs to

PLATES = (
    Plate("DECK", 0.0, 0.0, 20.0, 20.0, DECK_LAYUP, 0.9, 0.95, "adiabatic", (20.0, 20.0, 0.5)),
    Plate("WALL_N", 90.0, 0.0, 10.0, 3.0, WALL_LAYUP, 0.7, 0.88, "adiabatic", HOUSE),
    Plate("WALL_E", 90.0, 90.0, 10.0, 3.0, WALL_LAYUP, 0.7, 0.88, "adiabatic", HOUSE),
    Plate("WALL_S", 90.0, 180.0, 10.0, 3.0, WALL_LAYUP, 0.7, 0.88, "adiabatic", HOUSE),
    Plate("WALL_W", 90.0, 270.0, 10.0, 3.0, WALL_LAYUP, 0.7, 0.88, "adiabatic", HOUSE),
    Plate("INCLINED", 45.0, 180.0, 10.0, 10.0, WALL_LAYUP, 0.7, 0.88, "adiabatic",
          (10.0, 7.07, 7.07)),
    Plate("BULKHEAD", 90.0, 270.0, 10.0, 3.0, BULKHEAD_LAYUP, 0.7, 0.88, "room", HOUSE),
    Plate("BULKHEAD_TARP", 90.0, 270.0, 10.0, 3.0, BULKHEAD_LAYUP, 0.7, 0.88, "tarp", HOUSE),
)

STEPS = ("default", "convection", "sky", "matched")
"""Our side from its own choices to EnergyPlus's, one term at a time: ``default``; DOE-2
convection (``convection``); then the Perez sky instead of the isotropic one (``sky``); then
the ground instead of the sea below (``matched``)."""


# ------------------------------------------------------------------------------------------
# EnergyPlus input
# ------------------------------------------------------------------------------------------
def _rectangle(plate: Plate, x0: float) -> np.ndarray:
    """The plate's corners, counter-clockwise seen from outside, centroid at (x0, 0, 10)."""
    n = plate.normal
    a = np.radians(plate.azimuth)
    u = np.array([np.cos(a), -np.sin(a), 0.0])           # horizontal, along the width
    w = np.cross(n, u)                                    # along the slope
    if w[2] < 0 or (abs(w[2]) < 1e-12 and w @ np.array([0, 1.0, 0]) < 0):
        w = -w
    c = np.array([x0, 0.0, CENTROID_HEIGHT])
    hw, hh = 0.5 * plate.width * u, 0.5 * plate.height * w
    corners = np.array([c - hw + hh, c - hw - hh, c + hw - hh, c + hw + hh])
    if np.cross(corners[1] - corners[0], corners[2] - corners[1]) @ n < 0:
        corners = corners[::-1]
    return corners


def _box_faces(plate: Plate, x0: float, depth: float = 3.0):
    """The zone's faces: the plate (outer) and five adiabatic faces, each counter-clockwise
    seen from outside the box."""
    outer = _rectangle(plate, x0)
    inner = outer - depth * plate.normal
    centre = 0.5 * (outer.mean(axis=0) + inner.mean(axis=0))
    faces = [("OUT", outer), ("BACK", inner[::-1])]
    for i in range(4):
        j = (i + 1) % 4
        quad = np.array([outer[j], outer[i], inner[i], inner[j]])
        nrm = np.cross(quad[1] - quad[0], quad[2] - quad[1])
        if nrm @ (quad.mean(axis=0) - centre) < 0:
            quad = quad[::-1]
        faces.append((f"SIDE{i}", quad))
    return faces


def _kind(normal_z: float) -> str:
    return "Roof" if normal_z > 0.5 else ("Floor" if normal_z < -0.5 else "Wall")


OUTPUT_VARIABLES = SURFACE_OUTPUTS + (
    "Surface Outside Face Outdoor Air Drybulb Temperature",
    "Surface Outside Face Outdoor Air Wind Speed",
    "Surface Outside Face Outdoor Air Wind Direction",
    "Surface Inside Face Convection Heat Transfer Coefficient",
) + SITE_OUTPUTS


def write_idf(path, plates=PLATES, weeks=("july", "january"), version: str = "25.2") -> None:
    """The EnergyPlus input for ``plates`` over the weeks."""
    o = idf_object
    parts = [
        o("Version", version),
        o("SimulationControl", "No", "No", "No", "No", "Yes", "No", 1),
        o("Building", "ship boundary peer", 0, "Country", 0.001, 0.001, "MinimalShadowing",
          50, 20),
        o("Timestep", TIMESTEPS_PER_HOUR),
        # sun positions every day (the default 20-day reuse shifts January's noon sun by ~1°)
        o("ShadowCalculation", "PolygonClipping", "Periodic", 1),
        o("HeatBalanceAlgorithm", "ConductionTransferFunction"),
        o("SurfaceConvectionAlgorithm:Inside", "TARP"),
        o("SurfaceConvectionAlgorithm:Outside", "DOE-2"),
        o("GlobalGeometryRules", "UpperLeftCorner", "Counterclockwise", "World"),
        o("ZoneCapacitanceMultiplier:ResearchSpecial", "frozen air", "", 1.0e7, 1, 1, 1),
        o("Site:GroundReflectance", *([GROUND_REFLECTANCE] * 12)),
        o("OutputControl:Files", "Yes"),
    ]
    for name, (month, day) in WEEKS.items():
        if name in weeks:
            parts.append(o("RunPeriod", name, month, day, "", month, day + 6, "", "", "No",
                           "No", "No", "No", "No", "No"))
    parts.append(o("Material", "board", "Smooth", 0.0127, 0.16, 784.9, 830.0, 0.9, 0.5, 0.5))
    parts.append(o("Construction", "board", "board"))
    for k, p in enumerate(plates):
        names = []
        for i, layer in enumerate(p.layup.layers):
            m = p.layup.materials[i]
            outer, inner = i == 0, i == len(p.layup.layers) - 1
            therm = p.epsilon if outer else (0.9 if (inner and p.inside == "tarp")
                                             else (INNER_ABSORPTANCE if inner else 0.9))
            solar = p.alpha if outer else 0.5
            mname = f"{p.name}_{i}"
            parts.append(o("Material", mname, ROUGHNESS, layer.thickness, m.conductivity,
                           m.density, m.specific_heat, therm, solar, solar))
            names.append(mname)
        parts.append(o("Construction", p.name, *names))
        x0 = 60.0 * k
        parts.append(o("Zone", p.name, 0, 0, 0, 0))
        for tag, verts in _box_faces(p, x0):
            nz = np.cross(verts[1] - verts[0], verts[2] - verts[1])
            nz = nz[2] / np.linalg.norm(nz)
            if tag == "OUT":
                parts.append(idf_surface(p.name, _kind(nz), p.name, p.name, "Outdoors",
                                         "SunExposed", "WindExposed", verts))
            else:
                parts.append(idf_surface(f"{p.name}_{tag}", _kind(nz), "board", p.name,
                                         "Adiabatic", "NoSun", "NoWind", verts))
        if p.inside != "tarp":
            film = INSIDE_FILMS[p.inside]
            parts.append(o("SurfaceProperty:ConvectionCoefficients", p.name, "Inside", "Value",
                           film, "", ""))
    for var in OUTPUT_VARIABLES:
        parts.append(o("Output:Variable", "*", var, "Timestep"))
    path.write_text("\n".join(parts), encoding="ascii")


def run_energyplus(climate: str, weeks=("july", "january"), workdir=None, plates=PLATES,
                   epw=None) -> tuple:
    """One EnergyPlus run of every plate on a climate's TMY3 file (or the EPW file ``epw``):
    (outputs, wall time [s], work folder)."""
    return run_energyplus_idf(lambda path, version: write_idf(path, plates=plates, weeks=weeks,
                                                              version=version),
                              climate, workdir, epw=epw)


# ------------------------------------------------------------------------------------------
# Our side
# ------------------------------------------------------------------------------------------
TERMS = ("Temperature", "Convection Heat Transfer Coefficient",
         "Convection Heat Gain Rate per Area", "Net Thermal Radiation Heat Gain Rate per Area",
         "Solar Radiation Heat Gain Rate per Area", "Conduction Heat Transfer Rate per Area",
         "Incident Solar Radiation Rate per Area")


@dataclasses.dataclass
class Week:
    """What both codes see of one week on EnergyPlus's steps (index = step end; row 0 =
    00:00 of the first day)."""

    times: np.ndarray            # [s] after 00:00 of the first day
    weather: pd.DataFrame        # forcing_on_steps
    zenith: np.ndarray           # [deg] (pvlib SPA at the step end)
    azimuth: np.ndarray
    eplus: dict                  # plate → {variable: (n,) array on the steps (no row 0)}
    room: dict                   # plate → zone air [K]


def week_inputs(climate: str, df: pd.DataFrame, week: str, plates=PLATES, epw_path=None) -> Week:
    epw, loc = read_epw(epw_path or weather_file(climate))
    month, day = WEEKS[week]
    rows = week_rows(df, month)
    wx = forcing_on_steps(epw, loc, month, day, 7)
    zen, azi = sun_position(wx.index, loc)
    eplus = {}
    for p in plates:
        ev = {v: eplus_column(df, p.name, f"Surface Outside Face {v}")[rows] for v in
              ("Temperature", "Convection Heat Transfer Coefficient",
               "Convection Heat Gain Rate per Area",
               "Net Thermal Radiation Heat Gain Rate per Area",
               "Solar Radiation Heat Gain Rate per Area",
               "Conduction Heat Transfer Rate per Area",
               "Incident Solar Radiation Rate per Area", "Outdoor Air Drybulb Temperature",
               "Outdoor Air Wind Speed", "Outdoor Air Wind Direction")}
        ev["Inside Face Temperature"] = eplus_column(df, p.name,
                                                     "Surface Inside Face Temperature")[rows]
        ev["Zone Mean Air Temperature"] = eplus_column(df, p.name, "Zone Mean Air "
                                                       "Temperature")[rows]
        ev["Inside Convection Heat Transfer Coefficient"] = eplus_column(
            df, p.name, "Surface Inside Face Convection Heat Transfer Coefficient")[rows]
        eplus[p.name] = ev
    room = {p.name: float(np.mean(eplus[p.name]["Zone Mean Air Temperature"])) + 273.15
            for p in plates}
    times = (wx.index - wx.index[0]).total_seconds().to_numpy()
    return Week(times, wx, zen, azi, eplus, room)


def _on_steps(values: np.ndarray) -> np.ndarray:
    """EnergyPlus's step series (ending at each step end, no 00:00 row) with the first step's
    value at 00:00 in front: one value per step end from 00:00."""
    return np.concatenate([values[:1], values])


def incident(plate: Plate, wk: Week, sky: str, below: str) -> dict:
    """Irradiance on the plate [W m-2] per step end: beam, sky diffuse (``'perez'`` /
    ``'isotropic'``), from below (``'ground'``: albedo 0.2 of the global; ``'sea'``: the
    sea's reflected sun, :func:`shipthermal.environment.sea.sea_reflected_shortwave`)."""
    wx = wk.weather
    dni, dhi = wx["dni"].to_numpy(), wx["dhi"].to_numpy()
    zen, azi = wk.zenith, wk.azimuth
    up = zen < 90.0
    mu = np.clip(np.cos(np.radians(zen)), 0.0, None)
    s = np.stack([np.sin(np.radians(zen)) * np.sin(np.radians(azi)),
                  np.sin(np.radians(zen)) * np.cos(np.radians(azi)), np.cos(np.radians(zen))],
                 axis=-1)
    cos_inc = np.clip(s @ plate.normal, 0.0, None)
    beam = np.where(up, dni * cos_inc, 0.0)
    ghi = np.where(up, dni * mu, 0.0) + dhi
    f_sky = 0.5 * (1.0 + np.cos(np.radians(plate.tilt)))
    f_gnd = 1.0 - f_sky
    if sky == "perez":
        dni_extra = pvlib.irradiance.get_extra_radiation(wx.index)
        am = pvlib.atmosphere.get_relative_airmass(np.minimum(zen, 90.0), model="kasten1966")
        diffuse = pvlib.irradiance.perez(plate.tilt, plate.azimuth, dhi, dni,
                                         np.asarray(dni_extra), zen, azi,
                                         np.nan_to_num(np.asarray(am), nan=0.0),
                                         model="allsitescomposite1990")
        diffuse = np.nan_to_num(np.asarray(diffuse, dtype=float), nan=0.0)
        diffuse = np.where(up, diffuse, f_sky * dhi)
    else:
        diffuse = f_sky * dhi
    if below == "ground":
        reflected = GROUND_REFLECTANCE * ghi * f_gnd
    else:
        reflected = sea.sea_reflected_shortwave(np.where(up, dni, 0.0), dhi, zen) * f_gnd
    return {"beam": beam, "diffuse": diffuse, "reflected": reflected,
            "total": beam + diffuse + reflected}


def _longwave_in(plate: Plate, wk: Week, air: np.ndarray, below: str) -> np.ndarray:
    """Incident long-wave [W m-2] per step end: EnergyPlus's split of the file's sky
    (``F_sky β`` sky, ``F_sky (1 − β)`` air, ``F_gnd`` ground at the air temperature) or the
    ship forcing's (``F_sky`` sky, ``F_sea`` the sea's emitted and reflected long-wave)."""
    lw_sky = wk.weather["longwave_down"].to_numpy()
    cos_t = np.cos(np.radians(plate.tilt))
    f_sky = 0.5 * (1.0 + cos_t)
    f_gnd = 1.0 - f_sky
    if below == "ground":
        beta = np.sqrt(f_sky)
        return f_sky * beta * lw_sky + (f_sky * (1.0 - beta) + f_gnd) * SIGMA * air ** 4
    t_sea = float(np.mean(wk.weather["temp_air"]))           # ASSUMPTION (module notes)
    wind = wk.weather["wind_speed"].to_numpy()
    lw_sea = sea.sea_longwave_up(t_sea, lw_sky, optics.sea_emissivity_rough(wind))
    return f_sky * lw_sky + f_gnd * lw_sea


def _windward(plate: Plate, direction: np.ndarray) -> np.ndarray:
    """EnergyPlus's ``Windward``: horizontal faces, or within 90° of the wind."""
    if abs(np.cos(np.radians(plate.tilt))) >= conv.WINDWARD_HORIZONTAL_COS:
        return np.ones_like(direction, dtype=bool)
    d = np.abs(direction - plate.azimuth)
    d = np.where(d - 180.0 > 0.001, d - 360.0, d)
    return np.abs(d) - 90.0 <= 0.001


def _convection(plate: Plate, wk: Week, model: str, air: np.ndarray):
    """``(h_forced(t), law(t))`` on the steps for our model: DOE-2 with EnergyPlus's surface
    wind and direction (R_f of 'smooth'), or the default at the file's wind over the part's
    box (the forcing's flow lengths)."""
    ev = wk.eplus[plate.name]
    nz = float(np.cos(np.radians(plate.tilt)))
    n = len(wk.times)
    if model == "doe2":
        wind = _on_steps(ev["Outdoor Air Wind Speed"])
        direction = _on_steps(ev["Outdoor Air Wind Direction"])
        flow = conv.ExteriorFlow(normal_z=np.full(n, nz), wind_speed=wind,
                                 windward=_windward(plate, direction),
                                 roughness=conv.ROUGHNESS_MULTIPLIERS["smooth"])
    else:
        wind = wk.weather["wind_speed"].to_numpy()
        direction = np.radians(wk.weather["wind_direction"].to_numpy())
        bx, by, bz = plate.box
        flow = conv.ExteriorFlow(normal_z=np.full(n, nz), wind_speed=wind,
                                 length_flow=bx * np.abs(np.sin(direction))
                                 + by * np.abs(np.cos(direction)),
                                 length_vertical=bz,
                                 length_horizontal=bx * by / (2.0 * (bx + by)))
    m = conv.CONVECTION_MODELS[model]
    hf, law = m.terms(air, flow)          # air properties at the air temperature's film
    return np.asarray(hf, dtype=float), law


class _Rows:
    """Linear interpolation in time of a ``(n_steps, ...)`` table (exact at the steps)."""

    def __init__(self, times, values):
        self.times = np.asarray(times, dtype=float)
        self.values = np.asarray(values, dtype=float)

    def __call__(self, t):
        tt = self.times
        i = int(np.clip(np.searchsorted(tt, t, side="right") - 1, 0, len(tt) - 2))
        w = (t - tt[i]) / (tt[i + 1] - tt[i])
        if w <= 1e-12:
            return self.values[i]
        if w >= 1.0 - 1e-12:
            return self.values[i + 1]
        return (1.0 - w) * self.values[i] + w * self.values[i + 1]


def _plate_inputs(p: Plate, wk: Week, step: str) -> dict:
    """One plate's boundary inputs on the steps for one of :data:`STEPS`."""
    sky = "perez" if step in ("sky", "matched") else "isotropic"
    below = "ground" if step == "matched" else "sea"
    model = "doe2" if step in ("convection", "sky", "matched") else DEFAULT_CONVECTION_MODEL
    ev = wk.eplus[p.name]
    air = _on_steps(ev["Outdoor Air Drybulb Temperature"]) + 273.15 \
        if step != "default" else wk.weather["temp_air"].to_numpy()
    sun = incident(p, wk, sky, below)
    hf, law = _convection(p, wk, model, air)
    n = len(wk.times)
    if p.inside in INSIDE_FILMS:
        h_in = np.full(n, INSIDE_FILMS[p.inside])
    elif step == "default":
        h_in = np.full(n, BULKHEAD_ROOM_FILM)
    else:
        # EnergyPlus's own inside convection (its reported coefficient); its radiation to
        # the zone's other faces is not replayed
        h_in = _on_steps(ev["Inside Convection Heat Transfer Coefficient"])
    return {"absorbed": p.alpha * sun["total"], "incident": sun["total"],
            "longwave_in": _longwave_in(p, wk, air, below), "air": air, "h_forced": hf,
            "natural": np.asarray(law.natural, dtype=float),
            "blend": float(np.asarray(law.blend).ravel()[0]),
            "multiplier": float(np.asarray(law.multiplier).ravel()[0]),
            "normal_z": float(np.cos(np.radians(p.tilt))), "h_inside": h_in,
            "room": wk.room[p.name]}


def run_ours(wk: Week, steps=("default", "matched"), plates=PLATES, scheme: str = "bdf2"
             ) -> tuple:
    """Our solver on every plate for one week and the given :data:`STEPS`, all in one shell
    graph (a part per layup, two triangles per plate and step); returns
    ``{(step, plate): {term: (n,) array}}`` on EnergyPlus's steps (no 00:00 row) and the
    wall time [s]."""
    cases = [(step, p) for step in steps for p in plates]
    layups = {}
    for _, p in cases:
        layups.setdefault(p.layup.name, p.layup)
    parts = list(layups)
    verts, faces, part = [], [], []
    for k, (_, p) in enumerate(cases):
        base = 4 * k
        verts += [[2.0 * k, 0, 0], [2.0 * k + 1, 0, 0], [2.0 * k + 1, 1, 0], [2.0 * k, 1, 0]]
        faces += [[base, base + 1, base + 2], [base, base + 2, base + 3]]
        part += [parts.index(p.layup.name)] * 2
    g = build_shell_graph(np.array(verts, float), np.array(faces), np.array(part), parts,
                          layups)
    t = wk.times
    inputs = [_plate_inputs(p, wk, step) for step, p in cases]
    cond, where = {}, {}
    for name in parts:
        idx = g.patch_faces(f"{name}:outer")
        inner = g.patch_faces(f"{name}:inner")
        # the case of each face of the patch (faces in triangle order: face k of the
        # surface is triangle k)
        case_of = np.array([k // 2 for k in range(len(faces))])
        n_surf = len(faces)
        out_case = case_of[idx]
        in_case = case_of[inner - n_surf] if np.all(inner >= n_surf) else case_of[inner]
        where[name] = (idx, out_case)

        def col(key, cases_):
            return np.stack([np.broadcast_to(inputs[c][key], (len(t),) + np.shape(
                inputs[c][key])[1:]) for c in cases_], axis=1)

        natural = _Rows(t, col("natural", out_case))
        cond[f"{name}:outer"] = SurfaceBalance(
            absorbed_shortwave=_Rows(t, col("absorbed", out_case)),
            emissivity=np.array([cases[c][1].epsilon for c in out_case]),
            longwave_in=_Rows(t, col("longwave_in", out_case)),
            h=_Rows(t, col("h_forced", out_case)), temp_air=_Rows(t, col("air", out_case)),
            law=ConvectionLaw(natural=natural,
                              blend=np.array([inputs[c]["blend"] for c in out_case]),
                              multiplier=np.array([inputs[c]["multiplier"] for c in out_case]),
                              normal_z=np.array([inputs[c]["normal_z"] for c in out_case])))
        cond[f"{name}:inner"] = SurfaceBalance(
            h=_Rows(t, col("h_inside", in_case)),
            temp_air=np.array([inputs[c]["room"] for c in in_case]))
    t0 = float(np.mean(wk.weather["temp_air"].to_numpy()[:TIMESTEPS_PER_HOUR]))
    m = ThermalModel(g, cond, initial_temperature=t0)
    sim = Simulation(m, TIME_STEP, t[-1], scheme=scheme, output_times=t)
    c0 = time.perf_counter()
    res = sim.run(progress=False)
    wall = time.perf_counter() - c0
    out = {}
    for name in parts:
        idx, out_case = where[name]
        for j, c in enumerate(out_case):
            step, p = cases[c]
            if (step, p.name) in out:
                continue
            d = inputs[c]
            face = idx[j]
            ts = res.face_temperature[:, face]
            law = ConvectionLaw(d["natural"], d["blend"], d["multiplier"], d["normal_z"])
            h = law_h(d["h_forced"], law, ts - d["air"])
            out[(step, p.name)] = {
                "Temperature": ts[1:] - 273.15,
                "Convection Heat Transfer Coefficient": h[1:],
                "Convection Heat Gain Rate per Area": (h * (d["air"] - ts))[1:],
                "Net Thermal Radiation Heat Gain Rate per Area":
                    (p.epsilon * (d["longwave_in"] - SIGMA * ts ** 4))[1:],
                "Solar Radiation Heat Gain Rate per Area": d["absorbed"][1:],
                "Conduction Heat Transfer Rate per Area":
                    -res.face_flow[1:, face] / g.bface_area[face],
                "Incident Solar Radiation Rate per Area": d["incident"][1:],
            }
    return out, wall


def compare(climate: str, df: pd.DataFrame, steps=("default", "matched"),
            weeks=("july", "january"), plates=PLATES, epw=None, **kwargs) -> dict:
    """``{(step, week, plate): CaseResult}``: our solver next to EnergyPlus (one solver run
    per week holding every step and plate)."""
    out = {}
    for week in weeks:
        wk = week_inputs(climate, df, week, plates, epw)
        ours, wall = run_ours(wk, steps, plates, **kwargs)
        for (step, name), terms in ours.items():
            ev = {k: wk.eplus[name][k] for k in TERMS}
            out[(step, week, name)] = CaseResult(climate, week, name, ev, terms,
                                                 wall / len(ours))
    return out
