"""Convective heat-transfer coefficients for ship faces.

Pure vectorised functions over per-face arrays:

* fluid properties of air (film temperature) and sea water,
* the wind relative to a moving ship (apparent wind),
* forced convection over flat plates (laminar, turbulent, mixed boundary layer),
* natural convection for vertical, horizontal (facing up / down) and tilted plates,
* mixed forced + natural convection (Churchill 1977, n = 3),
* the building-envelope correlations of the EnergyPlus family (DOE-2, TARP, MoWiTT,
  McAdams, ISO 6946),
* wetted hull to sea water, inner faces to compartment air (ISO 6946 or natural).

The exterior models of :data:`CONVECTION_MODELS` give their coefficient as a forced part and
a law of the surface temperature (:class:`shipthermal.conditions.ConvectionLaw`), which the
solver evaluates at the surface temperature it solves for.

Temperatures in K, speeds in m/s, lengths in m, coefficients h in W m-2 K-1.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from shipthermal.conditions import LAW_PARAMETERS, ConvectionLaw, law_h
from shipthermal.errors import InputError, check_positive
from shipthermal.parameters import CONVECTION_MODEL_SOURCES, DEFAULT_CONVECTION_MODEL
from shipthermal.units import SIGMA, ZERO_CELSIUS

__all__ = [
    "G",
    "FluidProperties",
    "air_properties",
    "seawater_properties",
    "relative_wind",
    "wind_speed_at_height",
    "SEA_ROUGHNESS_LENGTH",
    "reynolds",
    "nusselt_forced_flat_plate",
    "nusselt_vertical_plate",
    "nusselt_horizontal_plate",
    "rayleigh",
    "h_forced",
    "h_natural",
    "combine_mixed",
    "h_exterior_air",
    "h_hull_water",
    "h_interior_iso6946",
    "h_interior",
    "ISO6946_INTERIOR_CONVECTION",
    "h_exterior_iso6946",
    "h_exterior_air_turbulent",
    "h_natural_walton",
    "h_exterior_doe2",
    "h_exterior_tarp",
    "h_exterior_mowitt",
    "is_windward",
    "WALTON_UNSTABLE",
    "WALTON_STABLE",
    "ASHRAE_VERTICAL",
    "MOWITT_NATURAL",
    "MOWITT_FORCED",
    "SPARROW_FORCED",
    "MCADAMS",
    "ROUGHNESS_MULTIPLIERS",
    "roughness_multiplier",
    "ExteriorFlow",
    "ConvectionModel",
    "CONVECTION_MODELS",
    "DEFAULT_CONVECTION_MODEL",
    "convection_model",
]

G = 9.80665
"""Standard gravity [m s-2]."""

_R_AIR = 287.05  # specific gas constant of dry air [J kg-1 K-1]


class FluidProperties(NamedTuple):
    """Fluid properties (arrays broadcast like the input temperature)."""

    density: np.ndarray            #: [kg m-3]
    viscosity: np.ndarray          #: dynamic viscosity [Pa s]
    conductivity: np.ndarray       #: thermal conductivity [W m-1 K-1]
    heat_capacity: np.ndarray      #: specific heat at constant pressure [J kg-1 K-1]
    expansion: np.ndarray          #: volumetric thermal expansion coefficient [K-1]

    @property
    def kinematic_viscosity(self):
        """[m2 s-1]"""
        return self.viscosity / self.density

    @property
    def diffusivity(self):
        """Thermal diffusivity [m2 s-1]."""
        return self.conductivity / (self.density * self.heat_capacity)

    @property
    def prandtl(self):
        """Prandtl number [-]."""
        return self.viscosity * self.heat_capacity / self.conductivity


def air_properties(temp_film, pressure=101325.0) -> FluidProperties:
    """Dry air properties as functions of the film temperature.

    Parameters
    ----------
    temp_film : array_like
        Film temperature ``(T_surface + T_air) / 2`` [K].
    pressure : array_like
        Static pressure [Pa].

    Returns
    -------
    FluidProperties

    Notes
    -----
    Density: ideal gas, R = 287.05 J kg-1 K-1. Viscosity: Sutherland's law,
    μ = 1.716e-5 (T/273.15)^1.5 (273.15 + 110.4)/(T + 110.4) Pa s. Conductivity:
    Sutherland form with k0 = 0.0241 W m-1 K-1, S = 194 K (White, Viscous Fluid
    Flow, 3rd ed., Table 1-3; ±2 % for 160–1000 K). cp: quadratic fit to the
    Incropera Table A.4 values (1.006, 1.007, 1.009, 1.014 kJ kg-1 K-1 at 250,
    300, 350, 400 K; exact at those points).
    Expansion coefficient of an ideal gas: 1/T.
    """
    t = np.asarray(temp_film, dtype=float)
    rho = np.asarray(pressure, dtype=float) / (_R_AIR * t)
    ratio = t / 273.15
    ratio_15 = ratio * np.sqrt(ratio)  # (T/273.15)^1.5 of both Sutherland laws
    mu = 1.716e-5 * (273.15 + 110.4) * ratio_15 / (t + 110.4)
    k = 0.0241 * (273.15 + 194.0) * ratio_15 / (t + 194.0)
    t_300 = t - 300.0
    cp = 1007.0 + (0.03 + 4.0e-4 * t_300) * t_300
    return FluidProperties(rho, mu, k, cp, 1.0 / t)


def seawater_properties(temp, salinity=0.035) -> FluidProperties:
    """Sea water properties (0–40 degC, salinity 0–0.04 kg/kg).

    Parameters
    ----------
    temp : array_like
        Water temperature [K].
    salinity : float
        Absolute salinity [kg kg-1].

    Returns
    -------
    FluidProperties

    Notes
    -----
    Pure-water viscosity by the Vogel equation μ_w = 2.414e-5·10^(247.8/(T − 140)) Pa s
    (±2 % over 0–100 degC), scaled for salinity by Sharqawy, Lienhard & Zubair (2010),
    Desalin. Water Treat. 16, 354–380 (μ_sw = μ_w(1 + A S + B S²)).
    Conductivity: pure water, Ramires et al. (1995), J. Phys. Chem. Ref. Data 24,
    1377, k = 0.6065(−1.48445 + 4.12292 τ − 1.63866 τ²), τ = T/298.15 (sea water is
    ≈ 1 % lower at S = 0.035: neglected). Density 1025 kg m-3, cp 3990 J kg-1 K-1 and
    expansion 2.0e-4 K-1 are representative constants for S = 0.035 near 15 degC
    (Sharqawy et al. 2010 tables); their variation over 0–30 degC (< 0.5 %, < 1 %,
    and 0.5–3e-4 K-1) matters little for the coefficients computed here.
    """
    t = np.asarray(temp, dtype=float)
    tc = t - ZERO_CELSIUS
    mu_w = 2.414e-5 * 10.0 ** (247.8 / (t - 140.0))
    a = 1.541 + 1.998e-2 * tc - 9.52e-5 * tc ** 2
    b = 7.974 - 7.561e-2 * tc + 4.724e-4 * tc ** 2
    mu = mu_w * (1.0 + a * salinity + b * salinity ** 2)
    tau = t / 298.15
    k = 0.6065 * (-1.48445 + 4.12292 * tau - 1.63866 * tau ** 2)
    ones = np.ones_like(t)
    return FluidProperties(1025.0 * ones, mu, k, 3990.0 * ones, 2.0e-4 * ones)


def relative_wind(wind_speed, wind_direction, ship_speed=0.0, ship_heading=0.0):
    """Apparent wind felt on a moving ship.

    Parameters
    ----------
    wind_speed : array_like
        True wind speed over ground [m s-1].
    wind_direction : array_like
        True wind direction, meteorological convention: where the wind blows FROM,
        clockwise from north [deg].
    ship_speed : array_like
        Ship speed over ground [m s-1].
    ship_heading : array_like
        Ship heading, clockwise from north [deg].

    Returns
    -------
    speed : numpy.ndarray
        Apparent wind speed [m s-1].
    direction : numpy.ndarray
        Apparent wind direction, where it blows FROM, clockwise from north [deg, 0–360).
    angle_off_bow : numpy.ndarray
        Apparent wind direction relative to the bow, clockwise (0 = from dead ahead,
        90 = from starboard beam) [deg, 0–360).

    Notes
    -----
    Velocity triangle: v_apparent = v_wind − v_ship, with the air velocity
    (−U sin φ, −U cos φ) in East-North components for a wind from φ.
    """
    u = np.asarray(wind_speed, dtype=float)
    phi = np.radians(np.asarray(wind_direction, dtype=float))
    v = np.asarray(ship_speed, dtype=float)
    psi = np.radians(np.asarray(ship_heading, dtype=float))
    ax = -u * np.sin(phi) - v * np.sin(psi)
    ay = -u * np.cos(phi) - v * np.cos(psi)
    speed = np.sqrt(ax * ax + ay * ay)
    direction = np.degrees(np.arctan2(-ax, -ay)) % 360.0
    off_bow = (direction - np.degrees(psi)) % 360.0
    return speed, direction, off_bow


SEA_ROUGHNESS_LENGTH = 2.0e-4
"""Aerodynamic roughness length of open sea [m] (Wieringa 1992, J. Wind Eng. Ind.
Aerodyn. 41, 357–368, Table 1: "open sea, fetch at least 5 km", z0 = 0.0002 m)."""


def wind_speed_at_height(wind_speed, height, reference_height=10.0,
                         roughness_length=SEA_ROUGHNESS_LENGTH):
    """Wind speed at ``height`` from a speed measured at ``reference_height`` (neutral
    logarithmic profile over the sea).

    The one home of the wind profile: the forcing takes the 10 m wind to each face's height,
    the station readers take an anemometer's wind to 10 m (``height=10.0,
    reference_height=<anemometer height>``).

    Parameters
    ----------
    wind_speed : array_like
        Wind speed measured at ``reference_height`` [m s-1].
    height : array_like
        Height above the sea surface the speed is wanted at [m].
    reference_height : array_like
        Height above the sea surface the speed was measured at [m] (10 m: the weather's).
    roughness_length : float
        Aerodynamic roughness length of the sea [m] (:data:`SEA_ROUGHNESS_LENGTH`).

    Returns
    -------
    numpy.ndarray
        ``u(z_ref) ln(z / z0) / ln(z_ref / z0)`` [m s-1]; both heights are clipped below at
        10 roughness lengths (the log law's lower end: a face at the waterline takes the
        wind there). Anemometer heights are validated at the input
        (``weather.wind_height``).

    Notes
    -----
    Neutral surface layer, u(z) = (u*/κ) ln(z / z0) (Stull 1988, An Introduction to
    Boundary Layer Meteorology, eq. 9.7.5c); stability and the ship's own flow
    disturbance are ignored.
    """
    z0 = float(roughness_length)
    z = np.maximum(np.asarray(height, dtype=float), 10.0 * z0)
    z_ref = np.maximum(np.asarray(reference_height, dtype=float), 10.0 * z0)
    return np.asarray(wind_speed, dtype=float) * np.log(z / z0) / np.log(z_ref / z0)


def reynolds(speed, length, kinematic_viscosity):
    """Reynolds number ``U L / ν`` [-] (speed [m s-1], length [m], ν [m2 s-1])."""
    return np.asarray(speed, dtype=float) * np.asarray(length, dtype=float) / \
        np.asarray(kinematic_viscosity, dtype=float)


def rayleigh(temp_surface, temp_fluid, length, props: FluidProperties, gravity=G):
    """Rayleigh number ``g β |ΔT| L³ / (ν α)`` [-].

    Parameters
    ----------
    temp_surface, temp_fluid : array_like
        Surface and free-stream temperature [K].
    length : array_like
        Characteristic length [m].
    props : FluidProperties
        Fluid properties at the film temperature.
    gravity : array_like
        Gravity component driving the flow [m s-2].
    """
    dt = np.abs(np.asarray(temp_surface, dtype=float) - np.asarray(temp_fluid, dtype=float))
    length = np.asarray(length, dtype=float)
    # ν α = μ k / (ρ² cp)
    nu_alpha = props.viscosity * props.conductivity / (props.density ** 2 * props.heat_capacity)
    # g L³ first: it has the (usually per-face) shape of the geometry
    return np.asarray(gravity) * (length * length * length) * props.expansion * dt / nu_alpha


def nusselt_forced_flat_plate(re, pr, boundary_layer: str = "mixed", re_crit=5.0e5):
    """Average Nusselt number of an isothermal flat plate in parallel flow.

    Parameters
    ----------
    re : array_like
        Reynolds number on the plate length [-].
    pr : array_like
        Prandtl number [-] (0.6 ≤ Pr ≤ 60).
    boundary_layer : {'mixed', 'laminar', 'turbulent'}
        ``mixed``: laminar up to ``re_crit`` then turbulent (Incropera eq. 7.38,
        ``(0.037 Re^0.8 − A) Pr^1/3`` with A = 0.037 Re_c^0.8 − 0.664 Re_c^0.5);
        ``laminar``: 0.664 Re^1/2 Pr^1/3 (eq. 7.30); ``turbulent``: tripped at the
        leading edge, 0.037 Re^0.8 Pr^1/3 (eq. 7.41).
    re_crit : float
        Transition Reynolds number [-].

    Returns
    -------
    numpy.ndarray
        Nu_L [-].

    Notes
    -----
    Incropera, DeWitt, Bergman & Lavine, Fundamentals of Heat and Mass Transfer, 6th
    ed., §7.2–7.3. The mixed formula is the integral of the local laminar
    (0.332 Re_x^1/2 Pr^1/3) and turbulent (0.0296 Re_x^0.8 Pr^1/3) correlations.
    Below ``re_crit`` the mixed and laminar forms coincide.
    """
    if boundary_layer not in ("mixed", "laminar", "turbulent"):
        raise InputError("convection.boundary_layer", boundary_layer,
                         "must be 'mixed', 'laminar' or 'turbulent'")
    re = np.asarray(re, dtype=float)
    pr3 = np.asarray(pr, dtype=float) ** (1.0 / 3.0)
    if boundary_layer == "laminar":
        return 0.664 * np.sqrt(re) * pr3
    if boundary_layer == "turbulent":
        return 0.037 * re ** 0.8 * pr3
    a = 0.037 * re_crit ** 0.8 - 0.664 * re_crit ** 0.5
    return np.where(re <= re_crit, 0.664 * np.sqrt(re), 0.037 * re ** 0.8 - a) * pr3


def nusselt_vertical_plate(ra, pr):
    """Average Nusselt number of an isothermal vertical plate, Churchill & Chu (1975).

    ``Nu = {0.825 + 0.387 Ra^(1/6) / [1 + (0.492/Pr)^(9/16)]^(8/27)}²``, all Ra.

    Parameters
    ----------
    ra : array_like
        Rayleigh number on the plate height [-].
    pr : array_like
        Prandtl number [-].

    Notes
    -----
    Churchill & Chu (1975), Int. J. Heat Mass Transfer 18, 1323–1329, eq. 9;
    Incropera 6th ed. eq. 9.26.
    """
    ra = np.asarray(ra, dtype=float)
    x = 0.492 / np.asarray(pr, dtype=float)
    root = np.sqrt(x)
    x_9_16 = root * np.sqrt(np.sqrt(np.sqrt(root)))  # x^(9/16) = x^(1/2) x^(1/16)
    psi = (1.0 + x_9_16) ** (8.0 / 27.0)
    return (0.825 + 0.387 * np.cbrt(np.sqrt(ra)) / psi) ** 2


def nusselt_horizontal_plate(ra, unstable):
    """Average Nusselt number of a horizontal plate (length scale L = A/P).

    Parameters
    ----------
    ra : array_like
        Rayleigh number on L = area / perimeter [-].
    unstable : array_like of bool
        True for the buoyancy-unstable side (upper face of a hot plate or lower face of
        a cold plate), False for the stable side.

    Returns
    -------
    numpy.ndarray
        Nu_L [-].

    Notes
    -----
    Unstable side: Lloyd & Moran (1974), ASME 74-WA/HT-66: 0.54 Ra^1/4
    (10^4–10^7), 0.15 Ra^1/3 (10^7–10^11) (Incropera 6th ed. eqs. 9.30–9.31), taken as
    the larger of the two: they cross at Ra = 4.8e6, so between 4.8e6 and 1e7 the
    turbulent branch is used, at most 6 % above the laminar one, and Nu is continuous in
    Ra (as the solver's Newton iteration on the surface temperature needs). Used beyond
    those ranges as the nearest branch (the 1/3 law makes h independent of L, the usual
    extrapolation for large decks). Stable side: 0.52 Ra^1/5 (10^4–10^9, Pr ≥ 0.7),
    Incropera et al. 7th ed. §9.6.2 (after Radziemska & Lewandowski 2001, Appl. Energy
    68, 347–366); beyond 1e9 (ship decks reach 1e10–1e12) see the floor of
    :func:`h_natural`.
    """
    ra = np.asarray(ra, dtype=float)
    unstable = np.broadcast_to(np.asarray(unstable, dtype=bool), ra.shape)
    out = np.empty(ra.shape)
    r_u = ra[unstable]
    out[unstable] = np.maximum(0.54 * np.sqrt(np.sqrt(r_u)), 0.15 * np.cbrt(r_u))
    out[~unstable] = 0.52 * ra[~unstable] ** 0.2
    return out


def h_forced(speed, length, props: FluidProperties, boundary_layer: str = "mixed",
             re_crit=5.0e5):
    """Forced-convection coefficient of a flat plate [W m-2 K-1].

    Parameters
    ----------
    speed : array_like
        Free-stream speed parallel to the plate [m s-1].
    length : array_like
        Plate length along the flow [m].
    props : FluidProperties
        Fluid properties at the film temperature.
    boundary_layer, re_crit
        See :func:`nusselt_forced_flat_plate`.
    """
    length = np.asarray(length, dtype=float)
    re = reynolds(speed, length, props.kinematic_viscosity)
    nu = nusselt_forced_flat_plate(re, props.prandtl, boundary_layer, re_crit)
    return nu * props.conductivity / length


def h_natural(temp_surface, temp_fluid, normal_z, length_vertical, length_horizontal,
              props: FluidProperties):
    """Natural-convection coefficient of a plate of any tilt [W m-2 K-1].

    Parameters
    ----------
    temp_surface, temp_fluid : array_like
        Surface and fluid temperature [K].
    normal_z : array_like
        Upward component of the unit normal pointing INTO the fluid [-]
        (+1 a face looking up, −1 a face looking down, 0 a vertical face).
    length_vertical : array_like
        Plate height along the slope (vertical correlation) [m].
    length_horizontal : array_like
        Area / perimeter of the plate (horizontal correlations) [m].
    props : FluidProperties
        Fluid properties at the film temperature.

    Returns
    -------
    numpy.ndarray
        h [W m-2 K-1].

    Notes
    -----
    For a plate tilted θ from vertical, the vertical correlation (Churchill & Chu) is
    evaluated with g cos θ and the horizontal one (Lloyd & Moran for the unstable
    side, 0.52 Ra^1/5 for the stable side) with g sin θ, and the larger coefficient is
    taken, as recommended for inclined plates by Raithby & Hollands (1998), Handbook
    of Heat Transfer, 3rd ed., ch. 4 §"Inclined surfaces". This recovers each
    correlation exactly for vertical and horizontal plates.

    Stable side of a tilted or horizontal plate: at least Walton's stable correlation
    (:func:`h_natural_walton`, ``1.810 |ΔT|^1/3 / (1.382 + |cos Σ|)``). The laminar
    0.52 Ra^1/5 is stated for Ra ≤ 1e9; a deck of 10–100 m reaches 1e10–1e12 on calm
    nights, where it would give h ≈ 0.3–0.4 W m-2 K-1 and fall further with size.
    Walton's form (ASHRAE's turbulent large-plate coefficient, half the heated-upward
    value; Walton 1983, NBSIR 83-2655) is independent of size and is what building
    programs apply to roofs of any size; MoWiTT's calm-air term measured on full-scale
    surfaces, 0.84 |ΔT|^1/3 (Yazdanian & Klems 1994), is close to it (0.76 |ΔT|^1/3 for a
    horizontal face).
    """
    ts = np.asarray(temp_surface, dtype=float)
    tf = np.asarray(temp_fluid, dtype=float)
    nz = np.clip(np.asarray(normal_z, dtype=float), -1.0, 1.0)
    sin_t = np.abs(nz)
    cos_t = np.sqrt(np.clip(1.0 - nz ** 2, 0.0, 1.0))
    lv = np.asarray(length_vertical, dtype=float)
    lh = np.asarray(length_horizontal, dtype=float)
    # Ra = g L³ · β|ΔT| / (ν α): the second factor (Ra at g L³ = 1) once for both
    ra_unit = rayleigh(ts, tf, 1.0, props, 1.0)
    ra_v = ra_unit * (G * cos_t * (lv * lv * lv))
    ra_h = ra_unit * (G * sin_t * (lh * lh * lh))
    # hot face looking up, or cold face looking down: plume leaves the plate freely
    unstable = (ts - tf) * nz > 0.0
    h_v = nusselt_vertical_plate(ra_v, props.prandtl) * props.conductivity / lv
    h_h = nusselt_horizontal_plate(ra_h, unstable) * props.conductivity / lh
    # Churchill–Chu has a conduction floor 0.825² at Ra → 0; apply it only where the
    # plate is near vertical so a horizontal face does not inherit it.
    h_v = np.where(cos_t > 1e-12, h_v, 0.0)
    # the stable side's floor at ship scale (a vertical plate has no stable side)
    floor = np.where(~unstable & (sin_t > 0.0),
                     WALTON_STABLE[0] * np.cbrt(np.abs(ts - tf)) / (WALTON_STABLE[1] + sin_t),
                     0.0)
    return np.maximum(np.maximum(h_v, h_h), floor)


def combine_mixed(h_forced_, h_natural_, n: float = 3.0, opposing=False):
    """Mixed convection, Churchill (1977): ``h^n = h_F^n ± h_N^n``.

    Parameters
    ----------
    h_forced_, h_natural_ : array_like
        Forced and natural coefficients [W m-2 K-1] (≥ 0).
    n : float
        Blending exponent [-]; 3 for plates (Churchill 1977; Incropera §9.9).
    opposing : array_like of bool
        True where the buoyant flow opposes the forced flow (minus sign).

    Returns
    -------
    numpy.ndarray
        h [W m-2 K-1]; for opposing flows ``|h_F^n − h_N^n|^(1/n)``.

    Notes
    -----
    Churchill, S. W. (1977), "A comprehensive correlating equation for laminar,
    assisting, forced and free convection", AIChE J. 23, 10–16. Combining the
    coefficients rather than Nusselt numbers lets the two use their own length
    scales (identical when they share one). For arbitrary wind over ship faces the
    transverse/assisting '+' form is the default.
    """
    hf = np.asarray(h_forced_, dtype=float)
    hn = np.asarray(h_natural_, dtype=float)
    if n == 3.0:
        hf = hf * hf * hf
        hn = hn * hn * hn
    else:
        hf = hf ** n
        hn = hn ** n
    if np.ndim(opposing) == 0:
        total = hf - hn if opposing else hf + hn
    else:
        total = np.where(opposing, hf - hn, hf + hn)
    return np.abs(total) ** (1.0 / n)


def h_exterior_air(temp_surface, temp_air, normal_z, wind_speed_relative, length_flow,
                   length_vertical, length_horizontal, pressure=101325.0,
                   boundary_layer: str = "mixed"):
    """Mixed-convection coefficient of exposed (dry) ship faces to the wind [W m-2 K-1].

    Parameters
    ----------
    temp_surface : array_like
        Face temperature [K].
    temp_air : array_like
        Air temperature [K].
    normal_z : array_like
        Upward component of the outward unit normal [-].
    wind_speed_relative : array_like
        Apparent wind speed on the ship (:func:`relative_wind`) [m s-1].
    length_flow : array_like
        Length of the part along the flow (e.g. ship length for hull and deck,
        superstructure length for its faces) [m].
    length_vertical, length_horizontal : array_like
        Natural-convection lengths (height; area/perimeter) [m].
    pressure : float
        Air pressure [Pa].
    boundary_layer : str
        See :func:`nusselt_forced_flat_plate`.

    Notes
    -----
    Properties at the film temperature; forced: flat plate in parallel flow at the
    apparent wind speed; natural: :func:`h_natural`; combined by Churchill (1977),
    n = 3, '+' sign.
    """
    ts = np.asarray(temp_surface, dtype=float)
    ta = np.asarray(temp_air, dtype=float)
    props = air_properties(0.5 * (ts + ta), pressure)
    hf = h_forced(wind_speed_relative, length_flow, props, boundary_layer)
    hn = h_natural(ts, ta, normal_z, length_vertical, length_horizontal, props)
    return combine_mixed(hf, hn)


def h_hull_water(temp_surface, temp_sea, ship_speed, length_flow, draught,
                 current_speed=0.0, salinity=0.035):
    """Wetted-hull coefficient to sea water [W m-2 K-1].

    Parameters
    ----------
    temp_surface : array_like
        Wetted hull face temperature [K].
    temp_sea : array_like
        Sea temperature [K].
    ship_speed : array_like
        Ship speed through the water [m s-1].
    length_flow : array_like
        Waterline length [m].
    draught : array_like
        Height of the wetted side (vertical natural-convection length) [m].
    current_speed : array_like
        Water speed past a moored hull (tidal current) [m s-1]; added to the ship
        speed, so a moored ship in a current still sees forced convection.
    salinity : float
        [kg kg-1].

    Notes
    -----
    Forced: flat plate in water, mixed boundary layer (Incropera eq. 7.38; Pr ≈ 7–13
    is inside the correlation's 0.6–60 range); natural: Churchill & Chu vertical plate
    over the draught, the floor when moored in still water; combined by Churchill
    (1977), n = 3. Hull roughness and fouling raise the turbulent h (not modelled).
    """
    ts = np.asarray(temp_surface, dtype=float)
    tw = np.asarray(temp_sea, dtype=float)
    props = seawater_properties(0.5 * (ts + tw), salinity)
    speed = np.abs(np.asarray(ship_speed, dtype=float)) + \
        np.abs(np.asarray(current_speed, dtype=float))
    hf = h_forced(speed, length_flow, props, "mixed")
    ra = rayleigh(ts, tw, draught, props)
    hn = nusselt_vertical_plate(ra, props.prandtl) * props.conductivity / \
        np.asarray(draught, dtype=float)
    return combine_mixed(hf, hn)


ISO6946_INTERIOR_CONVECTION = {"up": 5.0, "horizontal": 2.5, "down": 0.7}
"""Convective coefficient h_ci of internal surfaces by heat-flow direction [W m-2 K-1]:
ISO 6946:2017 Annex C, C.3."""


def h_interior_iso6946(temp_surface, temp_room, normal_z, include_radiation=False,
                       emissivity=0.9):
    """Interior surface coefficient by ISO 6946:2017 Annex C [W m-2 K-1].

    Parameters
    ----------
    temp_surface : array_like
        Inner face temperature [K].
    temp_room : array_like
        Compartment air temperature [K].
    normal_z : array_like
        Upward component of the unit normal pointing INTO the room [-].
    include_radiation : bool
        Add the linearised radiative part ``ε h_r0`` with ``h_r0 = 4 σ T_m³`` (ISO 6946
        eq. C.4) — only if the caller does not model interior radiation itself.
    emissivity : float
        Hemispherical emissivity of the inner face [-].

    Returns
    -------
    numpy.ndarray
        h_ci (5.0 upward, 2.5 horizontal, 0.7 downward heat flow), plus ``ε h_r0``
        when requested.

    Notes
    -----
    ISO 6946:2017 Annex C, C.2: heat flow is "horizontal" within ±30° of the
    horizontal plane. The heat-flow direction is from the warmer side to the colder:
    a floor (normal up) warmer than the room loses heat upward, etc. With radiation
    the standard's R_si values follow (1/(2.5 + 0.9·5.13) ≈ 0.14 ≈ 0.13 m²K/W).
    """
    ts = np.asarray(temp_surface, dtype=float)
    tr = np.asarray(temp_room, dtype=float)
    nz = np.asarray(normal_z, dtype=float)
    # heat-flow direction (vertical component): surface→room along +n if surface warmer
    flow_z = np.sign(ts - tr) * nz
    sin30 = 0.5
    hci_ = ISO6946_INTERIOR_CONVECTION
    hci = np.where(flow_z > sin30, hci_["up"],
                   np.where(flow_z < -sin30, hci_["down"], hci_["horizontal"]))
    if include_radiation:
        tm = 0.5 * (ts + tr)
        hci = hci + emissivity * 4.0 * SIGMA * (tm * tm * tm)
    return hci


def h_interior(temp_surface, temp_room, normal_z, length_vertical=None,
               length_horizontal=None, method: str = "iso6946"):
    """Interior face coefficient to compartment air [W m-2 K-1].

    Parameters
    ----------
    temp_surface, temp_room : array_like
        [K].
    normal_z : array_like
        Upward component of the unit normal pointing into the room [-].
    length_vertical, length_horizontal : array_like, optional
        Needed for ``method='natural'`` [m].
    method : {'iso6946', 'natural'}
        ISO 6946 convective constants, or the natural-convection correlations of
        :func:`h_natural` in air at the film temperature.
    """
    if method == "iso6946":
        return h_interior_iso6946(temp_surface, temp_room, normal_z)
    if method == "natural":
        if length_vertical is None or length_horizontal is None:
            raise InputError("interior.length", None,
                             "method='natural' needs length_vertical and length_horizontal")
        check_positive("interior.length_vertical", length_vertical, "m")
        check_positive("interior.length_horizontal", length_horizontal, "m")
        ts = np.asarray(temp_surface, dtype=float)
        tr = np.asarray(temp_room, dtype=float)
        props = air_properties(0.5 * (ts + tr))
        return h_natural(ts, tr, normal_z, length_vertical, length_horizontal, props)
    raise InputError("interior.method", method, "must be 'iso6946' or 'natural'")


# ---------------------------------------------------------------------------------------
# Building-envelope correlations (EnergyPlus family)
# ---------------------------------------------------------------------------------------
WALTON_UNSTABLE = (9.482, 7.238)
"""Walton's (TARP) unstable natural convection ``9.482 |ΔT|^1/3 / (7.238 − |cos Σ|)``
[W m-2 K-4/3], [-]: Walton (1983), Thermal Analysis Research Program Reference Manual,
NBSIR 83-2655, "Surface Inside Heat Balances" pp. 79–80, as EnergyPlus evaluates it
(``CalcWaltonUnstableHorizontalOrTilt``)."""

WALTON_STABLE = (1.810, 1.382)
"""Walton's (TARP) stable natural convection ``1.810 |ΔT|^1/3 / (1.382 + |cos Σ|)``
[W m-2 K-4/3], [-] (same source)."""

ASHRAE_VERTICAL = 1.31
"""Natural convection of a large vertical plate, turbulent range, ``1.31 |ΔT|^1/3``
[W m-2 K-4/3]: ASHRAE Handbook of Fundamentals (2001) p. 3.12 Table 5; Walton's form for
a vertical face (``cos Σ = 0``)."""

MOWITT_NATURAL = 0.84
"""MoWiTT turbulent natural convection constant C_t [W m-2 K-4/3]: Yazdanian & Klems (1994),
ASHRAE Trans. 100(1), 1087–1096."""

MOWITT_FORCED = {"windward": (3.26, 0.89), "leeward": (3.55, 0.617)}
"""MoWiTT forced convection ``a V^b`` [W m-2 K-1 (m/s)^-b], [-]: Yazdanian & Klems (1994),
the coefficients EnergyPlus uses (``CalcMoWITTForcedWindward`` / ``...Leeward``)."""

SPARROW_FORCED = 2.537
"""TARP's forced convection ``2.537 W_f R_f (P V / A)^½`` [W m-2 K-1 (m/s)^-½ m^½]:
Sparrow, Ramsey & Mass (1979), J. Heat Transfer 101, 204, as adopted by Walton (1981, 1983);
W_f = 1 windward, 0.5 leeward."""

MCADAMS = (5.7, 3.8)
"""McAdams (1954), Heat Transmission, 3rd ed., as cast in SI by Palyvos (2008), Appl.
Therm. Eng. 28, 801–808: ``h = 5.7 + 3.8 V`` [W m-2 K-1], [J m-3 K-1]."""

ROUGHNESS_MULTIPLIERS = {"very_rough": 2.17, "rough": 1.67, "medium_rough": 1.52,
                         "medium_smooth": 1.13, "smooth": 1.11, "very_smooth": 1.00}
"""Surface roughness multipliers R_f of the forced convection of DOE-2 and TARP [-]: Walton
(1981), from the ASHRAE (1981) graph of surface conductance; example materials stucco,
brick, concrete, clear pine, smooth plaster, glass (EnergyPlus Engineering Reference,
"Surface Roughness Multipliers")."""

WINDWARD_HORIZONTAL_COS = 0.98
"""|cos tilt| at and above which a face counts as horizontal, hence windward (EnergyPlus's
``Windward`` function)."""


def h_natural_walton(temp_surface, temp_air, normal_z):
    """Walton's natural convection coefficient (TARP, DOE-2) [W m-2 K-1].

    Parameters
    ----------
    temp_surface, temp_air : array_like
        [K].
    normal_z : array_like
        Upward component of the outward unit normal, ``cos Σ`` [-].

    Returns
    -------
    numpy.ndarray
        ``9.482 |ΔT|^1/3 / (7.238 − |cos Σ|)`` on the unstable side (hot face looking up,
        cold face looking down), ``1.810 |ΔT|^1/3 / (1.382 + |cos Σ|)`` on the stable side,
        ASHRAE's vertical ``1.31 |ΔT|^1/3`` at ``cos Σ = 0`` (both forms are within 0.03 %
        of it there).

    Notes
    -----
    Walton (1983), NBSIR 83-2655, pp. 79–80, from the ASHRAE Handbook of Fundamentals
    turbulent coefficients of large vertical plates and of large horizontal plates (heated
    facing up; half of it facing down); EnergyPlus Engineering Reference, "TARP
    algorithm".
    """
    d = np.asarray(temp_surface, dtype=float) - np.asarray(temp_air, dtype=float)
    c = np.abs(np.asarray(normal_z, dtype=float))
    unstable = d * np.asarray(normal_z, dtype=float) > 0.0
    x3 = np.cbrt(np.abs(d))
    return x3 * np.where(c == 0.0, ASHRAE_VERTICAL,
                         np.where(unstable, WALTON_UNSTABLE[0] / (WALTON_UNSTABLE[1] - c),
                                  WALTON_STABLE[0] / (WALTON_STABLE[1] + c)))


def is_windward(normal, wind_from):
    """Whether faces face the wind (EnergyPlus's ``Windward``) [bool].

    Parameters
    ----------
    normal : array_like, (..., 3)
        Outward unit normals (any right-handed frame with z up) [-].
    wind_from : array_like, (..., 2)
        Horizontal unit vector pointing where the wind comes FROM, same frame [-].

    Returns
    -------
    numpy.ndarray
        True where ``|n_z| ≥ 0.98`` (a horizontal face is windward) or the face's azimuth is
        within 90° of the wind's direction (Walton 1981; EnergyPlus).
    """
    n = np.asarray(normal, dtype=float)
    w = np.asarray(wind_from, dtype=float)
    horizontal = np.abs(n[..., 2]) >= WINDWARD_HORIZONTAL_COS
    return horizontal | (n[..., 0] * w[..., 0] + n[..., 1] * w[..., 1] >= 0.0)


def h_exterior_mowitt(temp_surface, temp_air, wind_speed, windward=True):
    """MoWiTT exterior coefficient ``[(C_t |ΔT|^1/3)² + (a V^b)²]^½`` [W m-2 K-1].

    Parameters
    ----------
    temp_surface, temp_air : array_like
        [K].
    wind_speed : array_like
        Wind speed at the surface [m s-1].
    windward : array_like of bool
        Windward (a = 3.26, b = 0.89) or leeward (3.55, 0.617) coefficients.

    Notes
    -----
    Yazdanian & Klems (1994), ASHRAE Trans. 100(1), 1087–1096 (:data:`MOWITT_NATURAL`,
    :data:`MOWITT_FORCED`).
    """
    d = np.asarray(temp_surface, dtype=float) - np.asarray(temp_air, dtype=float)
    hf = _mowitt_forced(wind_speed, windward)
    hn = MOWITT_NATURAL * np.cbrt(np.abs(d))
    return np.sqrt(hn * hn + hf * hf)


def _mowitt_forced(wind_speed, windward):
    v = np.abs(np.asarray(wind_speed, dtype=float))
    ww = np.asarray(windward, dtype=bool)
    aw, bw = MOWITT_FORCED["windward"]
    al, bl = MOWITT_FORCED["leeward"]
    return np.where(ww, aw * v ** bw, al * v ** bl)


def h_exterior_doe2(temp_surface, temp_air, normal_z, wind_speed, windward=True,
                    roughness=1.0):
    """DOE-2 exterior coefficient ``h_n + R_f (h_glass − h_n)`` [W m-2 K-1].

    Parameters
    ----------
    temp_surface, temp_air : array_like
        [K].
    normal_z : array_like
        ``cos Σ`` of the outward normal [-].
    wind_speed : array_like
        Wind speed at the surface [m s-1].
    windward : array_like of bool
        MoWiTT's windward or leeward forced coefficients.
    roughness : array_like
        Roughness multiplier R_f [-] (:data:`ROUGHNESS_MULTIPLIERS`).

    Notes
    -----
    ``h_glass = (h_n² + (a V^b)²)^½`` with Walton's natural ``h_n``
    (:func:`h_natural_walton`) and MoWiTT's forced term: LBL (1994), DOE-2.1E-053 source
    code, as documented in the EnergyPlus Engineering Reference ("DOE-2 Model"); the
    default outside convection of EnergyPlus.
    """
    hn = h_natural_walton(temp_surface, temp_air, normal_z)
    hf = _mowitt_forced(wind_speed, windward)
    return hn + np.asarray(roughness, dtype=float) * (np.sqrt(hn * hn + hf * hf) - hn)


def h_exterior_tarp(temp_surface, temp_air, normal_z, wind_speed, perimeter_over_area,
                    windward=True, roughness=1.0):
    """TARP exterior coefficient ``h_f + h_n`` [W m-2 K-1].

    Parameters
    ----------
    temp_surface, temp_air : array_like
        [K].
    normal_z : array_like
        ``cos Σ`` of the outward normal [-].
    wind_speed : array_like
        Wind speed at the surface [m s-1].
    perimeter_over_area : array_like
        Perimeter / area of the facade or roof the face belongs to [m-1].
    windward : array_like of bool
        Wind-direction factor W_f = 1 (windward) or 0.5 (leeward).
    roughness : array_like
        R_f [-].

    Notes
    -----
    ``h_f = 2.537 W_f R_f (P V / A)^½`` (Sparrow, Ramsey & Mass 1979), Walton's natural
    ``h_n``: Walton (1983), NBSIR 83-2655; EnergyPlus Engineering Reference ("TARP").
    """
    hn = h_natural_walton(temp_surface, temp_air, normal_z)
    return hn + _sparrow_forced(wind_speed, perimeter_over_area, windward, roughness)


def _sparrow_forced(wind_speed, perimeter_over_area, windward, roughness):
    wf = np.where(np.asarray(windward, dtype=bool), 1.0, 0.5)
    v = np.abs(np.asarray(wind_speed, dtype=float))
    return SPARROW_FORCED * wf * np.asarray(roughness, dtype=float) * np.sqrt(
        np.asarray(perimeter_over_area, dtype=float) * v)


# ---------------------------------------------------------------------------------------
# Exterior convection models (registry)
# ---------------------------------------------------------------------------------------
def h_exterior_iso6946(temp_surface, temp_air, normal_z, wind_speed_relative, length_flow,
                       length_vertical, length_horizontal):
    """Exterior convective coefficient of ISO 6946:2017 Annex C, ``h_ce = 4 + 4 v``
    [W m-2 K-1].

    Parameters as :func:`h_exterior_air`; only ``wind_speed_relative`` (``v``, the wind
    speed next to the surface [m s-1]) enters: the coefficient is independent of the
    surface temperature, orientation and size.

    Notes
    -----
    ISO 6946:2017, Annex C, eq. (C.2) (the building standard's external surface
    convection; its radiative part ``ε h_r0`` is not included: the surface balance carries
    the long-wave exchange itself).
    """
    shape = np.broadcast_shapes(np.shape(temp_surface), np.shape(temp_air),
                                np.shape(wind_speed_relative))
    v = np.abs(np.asarray(wind_speed_relative, dtype=float))
    return np.broadcast_to(4.0 + 4.0 * v, shape).astype(float)


def h_exterior_air_turbulent(temp_surface, temp_air, normal_z, wind_speed_relative,
                             length_flow, length_vertical, length_horizontal):
    """:func:`h_exterior_air` with a boundary layer tripped at the leading edge
    [W m-2 K-1]: forced ``Nu = 0.037 Re^0.8 Pr^1/3`` (Incropera eq. 7.41), combined with
    natural convection by Churchill (1977), n = 3."""
    return h_exterior_air(temp_surface, temp_air, normal_z, wind_speed_relative, length_flow,
                          length_vertical, length_horizontal, boundary_layer="turbulent")


@dataclass(frozen=True)
class ExteriorFlow:
    """What an exterior convection model needs to know of each face and its wind.

    Arrays broadcast against each other (rows: times, columns: faces).

    Attributes
    ----------
    normal_z : array_like
        Upward component of the outward unit normal [-].
    wind_speed : array_like
        Wind speed at the face (apparent wind at its height) [m s-1].
    length_flow : array_like
        Length of the part along the wind [m] (flat-plate models).
    length_vertical, length_horizontal : array_like
        Natural-convection lengths: height; area / perimeter [m] (flat-plate models).
    windward : array_like of bool
        The face faces the wind (:func:`is_windward`) (DOE-2, TARP, MoWiTT).
    perimeter_over_area : array_like
        Of the facade or deck the face belongs to [m-1] (TARP).
    roughness : array_like
        Roughness multiplier R_f [-] (:data:`ROUGHNESS_MULTIPLIERS`; DOE-2, TARP).
    """

    normal_z: object
    wind_speed: object
    length_flow: object = 1.0
    length_vertical: object = 1.0
    length_horizontal: object = 1.0
    windward: object = True
    perimeter_over_area: object = 1.0
    roughness: object = 1.0


def _natural(shape) -> np.ndarray:
    return np.zeros(tuple(shape) + (2, len(LAW_PARAMETERS)))


def _walton_law(normal_z, shape) -> np.ndarray:
    """Walton's natural convection as a law (both sides ``c |ΔT|^1/3``)."""
    c = np.broadcast_to(np.abs(np.asarray(normal_z, dtype=float)), shape)
    nat = _natural(shape)
    nat[..., 0, 0] = np.where(c == 0.0, ASHRAE_VERTICAL,
                              WALTON_UNSTABLE[0] / (WALTON_UNSTABLE[1] - c))
    nat[..., 1, 0] = np.where(c == 0.0, ASHRAE_VERTICAL, WALTON_STABLE[0] / (WALTON_STABLE[1] + c))
    nat[..., :, 1] = 1.0 / 3.0
    return nat


def _flat_plate_law(temp_film, normal_z, length_vertical, length_horizontal, shape,
                    pressure=101325.0) -> np.ndarray:
    """:func:`h_natural` as a law at the film temperature's properties: the Churchill–Chu
    vertical term (g cos θ over the height), Lloyd & Moran's two unstable branches and the
    stable 0.52 Ra^1/5 (g sin θ over A/P), and Walton's stable floor."""
    props = air_properties(np.broadcast_to(np.asarray(temp_film, dtype=float), shape), pressure)
    nz = np.broadcast_to(np.clip(np.asarray(normal_z, dtype=float), -1.0, 1.0), shape)
    sin_t = np.abs(nz)
    cos_t = np.sqrt(np.clip(1.0 - nz ** 2, 0.0, 1.0))
    lv = np.broadcast_to(np.asarray(length_vertical, dtype=float), shape)
    lh = np.broadcast_to(np.asarray(length_horizontal, dtype=float), shape)
    k = props.conductivity
    # g β / (ν α): Ra per (K m³)
    ra_unit = G * props.expansion * props.density ** 2 * props.heat_capacity / (
        props.viscosity * props.conductivity)
    ra_h = ra_unit * sin_t * lh ** 3            # Ra_h / |ΔT|
    ra_v = ra_unit * cos_t * lv ** 3            # Ra_v / |ΔT|
    nat = _natural(shape)
    kh = k / lh
    nat[..., 0, 0] = 0.54 * kh * ra_h ** 0.25
    nat[..., 0, 1] = 0.25
    nat[..., 0, 2] = 0.15 * kh * np.cbrt(ra_h)
    nat[..., 0, 3] = 1.0 / 3.0
    nat[..., 1, 0] = 0.52 * kh * ra_h ** 0.2
    nat[..., 1, 1] = 0.2
    nat[..., 1, 2] = np.where(sin_t > 0.0, WALTON_STABLE[0] / (WALTON_STABLE[1] + sin_t), 0.0)
    nat[..., 1, 3] = 1.0 / 3.0
    # Churchill & Chu: h = (k/L)(0.825 + 0.387 Ra^(1/6)/ψ)² = (a + b |ΔT|^(1/6))²
    vertical = cos_t > 1e-12
    x = 0.492 / props.prandtl
    psi = (1.0 + x ** (9.0 / 16.0)) ** (8.0 / 27.0)
    root = np.sqrt(k / lv)
    a = np.where(vertical, 0.825 * root, 0.0)
    b = np.where(vertical, root * 0.387 / psi * ra_v ** (1.0 / 6.0), 0.0)
    nat[..., :, 4] = a[..., None]
    nat[..., :, 5] = b[..., None]
    return nat


def _terms_flat_plate(boundary_layer):
    def terms(temp_film, flow: ExteriorFlow, law: bool = True):
        shape = _flow_shape(temp_film, flow)
        props = air_properties(np.broadcast_to(np.asarray(temp_film, dtype=float), shape))
        hf = h_forced(flow.wind_speed, flow.length_flow, props, boundary_layer)
        if not law:
            return np.broadcast_to(hf, shape), None
        nat = _flat_plate_law(temp_film, flow.normal_z, flow.length_vertical,
                              flow.length_horizontal, shape)
        return np.broadcast_to(hf, shape), ConvectionLaw(nat, 3.0, 1.0, _bz(flow.normal_z, shape))
    return terms


def _flow_shape(temp_film, flow: ExteriorFlow) -> tuple:
    return np.broadcast_shapes(np.shape(temp_film), *(np.shape(getattr(flow, f.name))
                                                      for f in dataclasses.fields(flow)))


def _bz(value, shape) -> np.ndarray:
    return np.broadcast_to(np.asarray(value, dtype=float), shape)


def _terms_doe2(temp_film, flow: ExteriorFlow, law: bool = True):
    shape = _flow_shape(temp_film, flow)
    hf = _mowitt_forced(flow.wind_speed, flow.windward)
    if not law:
        return _bz(hf, shape), None
    return (_bz(hf, shape), ConvectionLaw(_walton_law(flow.normal_z, shape), 2.0,
                                          _bz(flow.roughness, shape), _bz(flow.normal_z, shape)))


def _terms_mowitt(temp_film, flow: ExteriorFlow, law: bool = True):
    shape = _flow_shape(temp_film, flow)
    if not law:
        return _bz(_mowitt_forced(flow.wind_speed, flow.windward), shape), None
    nat = _natural(shape)
    nat[..., :, 0] = MOWITT_NATURAL
    nat[..., :, 1] = 1.0 / 3.0
    hf = _mowitt_forced(flow.wind_speed, flow.windward)
    return _bz(hf, shape), ConvectionLaw(nat, 2.0, 1.0, _bz(flow.normal_z, shape))


def _terms_tarp(temp_film, flow: ExteriorFlow, law: bool = True):
    shape = _flow_shape(temp_film, flow)
    hf = _sparrow_forced(flow.wind_speed, flow.perimeter_over_area, flow.windward,
                         flow.roughness)
    if not law:
        return _bz(hf, shape), None
    return (_bz(hf, shape), ConvectionLaw(_walton_law(flow.normal_z, shape), 1.0, 1.0,
                                          _bz(flow.normal_z, shape)))


def _terms_linear(a, b):
    def terms(temp_film, flow: ExteriorFlow, law: bool = True):
        shape = _flow_shape(temp_film, flow)
        v = np.abs(np.asarray(flow.wind_speed, dtype=float))
        return _bz(a + b * v, shape), (ConvectionLaw(_natural(shape), 1.0, 1.0, 0.0) if law
                                       else None)
    return terms


@dataclass(frozen=True)
class ConvectionModel:
    """An exterior (air-side) convection correlation.

    Attributes
    ----------
    name : str
        Key in :data:`CONVECTION_MODELS`.
    terms : callable
        ``terms(temp_film [K], flow: ExteriorFlow, law=True) -> (h_forced [W m-2 K-1],
        ConvectionLaw or None)``: the forced part and the law of the surface temperature
        (:class:`shipthermal.conditions.ConvectionLaw`) that the solver evaluates at the
        solved surface temperature; air properties (flat-plate models) at ``temp_film``.
    source : str
        Where the correlation comes from.
    validity : str
        Range in which its source supports it.
    film_dependent : bool
        Its terms depend on ``temp_film`` (air properties).
    """

    name: str
    terms: Callable
    source: str
    validity: str
    film_dependent: bool = False
    direct: Callable | None = None

    def h_direct(self, temp_surface, temp_air, flow: ExteriorFlow):
        """The same coefficient from the correlation functions of this module (numpy, no
        law arrays: the fast path of the forcing's quasi-steady estimate) [W m-2 K-1]."""
        return self.direct(np.asarray(temp_surface, dtype=float),
                           np.asarray(temp_air, dtype=float), flow)

    def h(self, temp_surface, temp_air, flow: ExteriorFlow):
        """The coefficient at a surface temperature [W m-2 K-1] (film temperature
        ``(T_s + T_air)/2``), through :func:`shipthermal.conditions.law_h`: the function the
        solver evaluates."""
        ts = np.asarray(temp_surface, dtype=float)
        ta = np.asarray(temp_air, dtype=float)
        hf, law = self.terms(0.5 * (ts + ta), flow)
        return law_h(hf, law, ts - ta)


def _direct_flat_plate(boundary_layer):
    def h(ts, ta, f: ExteriorFlow):
        return h_exterior_air(ts, ta, f.normal_z, f.wind_speed, f.length_flow,
                              f.length_vertical, f.length_horizontal,
                              boundary_layer=boundary_layer)
    return h


def _direct_linear(a, b):
    def h(ts, ta, f: ExteriorFlow):
        shape = np.broadcast_shapes(ts.shape, ta.shape, np.shape(f.wind_speed))
        return np.broadcast_to(a + b * np.abs(np.asarray(f.wind_speed, dtype=float)),
                               shape).astype(float)
    return h


_MODEL_TERMS = {
    "flat_plate_mixed": (_terms_flat_plate("mixed"), True, _direct_flat_plate("mixed")),
    "flat_plate_turbulent": (_terms_flat_plate("turbulent"), True,
                             _direct_flat_plate("turbulent")),
    "doe2": (_terms_doe2, False, lambda ts, ta, f: h_exterior_doe2(
        ts, ta, f.normal_z, f.wind_speed, f.windward, f.roughness)),
    "tarp": (_terms_tarp, False, lambda ts, ta, f: h_exterior_tarp(
        ts, ta, f.normal_z, f.wind_speed, f.perimeter_over_area, f.windward, f.roughness)),
    "mowitt": (_terms_mowitt, False, lambda ts, ta, f: h_exterior_mowitt(
        ts, ta, f.wind_speed, f.windward)),
    "mcadams": (_terms_linear(*MCADAMS), False, _direct_linear(*MCADAMS)),
    "iso6946": (_terms_linear(4.0, 4.0), False, _direct_linear(4.0, 4.0))}

CONVECTION_MODELS: dict[str, ConvectionModel] = {
    name: ConvectionModel(name, _MODEL_TERMS[name][0], **info,
                          film_dependent=_MODEL_TERMS[name][1], direct=_MODEL_TERMS[name][2])
    for name, info in CONVECTION_MODEL_SOURCES.items()}
"""Exterior convection models by name (pvlib-style named set); names, sources and validity
from :data:`shipthermal.parameters.CONVECTION_MODEL_SOURCES`."""


def convection_model(name: str | ConvectionModel, field: str = "convection.model"
                     ) -> ConvectionModel:
    """Look a model up in :data:`CONVECTION_MODELS` (a :class:`ConvectionModel` passes
    through); an unknown name raises :class:`InputError` listing the known ones."""
    if isinstance(name, ConvectionModel):
        return name
    if name not in CONVECTION_MODELS:
        raise InputError(field, name, f"must be one of {', '.join(CONVECTION_MODELS)}",
                         "See shipthermal.environment.convection.CONVECTION_MODELS for the "
                         "sources and validity of each")
    return CONVECTION_MODELS[name]


def roughness_multiplier(name: str, field: str = "convection.roughness") -> float:
    """R_f of a roughness class (:data:`ROUGHNESS_MULTIPLIERS`); an unknown name raises
    :class:`InputError` listing the classes."""
    if name not in ROUGHNESS_MULTIPLIERS:
        raise InputError(field, name, f"must be one of {', '.join(ROUGHNESS_MULTIPLIERS)}",
                         "Walton's classes: stucco very_rough, brick rough, concrete "
                         "medium_rough, clear pine medium_smooth, smooth plaster smooth, "
                         "glass very_smooth")
    return ROUGHNESS_MULTIPLIERS[name]
