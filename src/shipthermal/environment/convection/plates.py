"""Flat-plate heat transfer: Reynolds, Rayleigh and Nusselt numbers, forced, natural (any
tilt) and mixed convection, and the coefficients built of them for exposed faces in the wind
and the wetted hull in sea water.

Temperatures in K, speeds in m/s, lengths in m, coefficients h in W m-2 K-1.

The functions are numpy array code, not compiled kernels: their cost is in the powers and
roots, which numpy evaluates with SIMD (here AVX-512: ``cbrt`` 2-4 ns and ``x ** 0.8``
5.5 ns an element) while a compiled loop calls the C library's scalar functions (21 ns each;
the llvmlite wheels carry no SVML). :func:`h_exterior_air` fused into one numba kernel took
1.3 - 1.6 s against numpy's 1.6 - 1.8 s for 144 x 40 288 faces on one thread (the frigate's
forcing tables at 0.5 m; timed in turn in one process): not worth a second copy of the
correlations.
"""

from __future__ import annotations

import numpy as np

from shipthermal.errors import InputError

from .envelope import WALTON_STABLE
from .fluids import G, FluidProperties, air_properties, seawater_properties


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



def h_exterior_air_turbulent(temp_surface, temp_air, normal_z, wind_speed_relative,
                             length_flow, length_vertical, length_horizontal):
    """:func:`h_exterior_air` with a boundary layer tripped at the leading edge
    [W m-2 K-1]: forced ``Nu = 0.037 Re^0.8 Pr^1/3`` (Incropera eq. 7.41), combined with
    natural convection by Churchill (1977), n = 3."""
    return h_exterior_air(temp_surface, temp_air, normal_z, wind_speed_relative, length_flow,
                          length_vertical, length_horizontal, boundary_layer="turbulent")
