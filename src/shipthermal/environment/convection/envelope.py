"""The building-envelope correlations of the EnergyPlus family for exterior faces: Walton's
natural convection (TARP, DOE-2), MoWiTT, DOE-2, TARP, ISO 6946, the windward test and the
roughness multipliers.

Temperatures in K, speeds in m/s, coefficients h in W m-2 K-1.
"""

from __future__ import annotations

import numpy as np

from shipthermal.errors import InputError


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



def roughness_multiplier(name: str, field: str = "convection.roughness") -> float:
    """R_f of a roughness class (:data:`ROUGHNESS_MULTIPLIERS`); an unknown name raises
    :class:`InputError` listing the classes."""
    if name not in ROUGHNESS_MULTIPLIERS:
        raise InputError(field, name, f"must be one of {', '.join(ROUGHNESS_MULTIPLIERS)}",
                         "Walton's classes: stucco very_rough, brick rough, concrete "
                         "medium_rough, clear pine medium_smooth, smooth plaster smooth, "
                         "glass very_smooth")
    return ROUGHNESS_MULTIPLIERS[name]
