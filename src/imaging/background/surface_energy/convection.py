"""Convective coefficients ``h(temp_surface, temp_air, wind_speed)`` of a ground pixel: the
project's exterior correlations, the logarithmic wind profile, a linear law."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from shipthermal.environment.convection import ExteriorFlow, convection_model
from shipthermal.errors import InputError, check_range
from shipthermal.parameters import DEFAULT_CONVECTION_MODEL

from .air import VON_KARMAN, air_heat_capacity


GROUND_CONVECTION_LENGTHS = {"length_flow": 30.0, "length_vertical": 30.0,
                             "length_horizontal": 7.5}
"""Characteristic lengths [m] of a ground pixel in the flat-plate correlations: the flow length
and the along-slope height are the 30 m of a Landsat pixel (ASSUMPTION: the scale the model
represents; with h ∝ L^-0.2 in turbulent forced flow, 10 m or 100 m change h by +25 % / −21 %),
the horizontal natural-convection length is area / perimeter of that square, 30/4 m (DERIVED);
above Ra ≈ 1e7 the horizontal coefficient does not depend on it (0.15 Ra^1/3)."""

# ---------------------------------------------------------------------------------------------
# Convection
# ---------------------------------------------------------------------------------------------
def convection_correlation(model: str = DEFAULT_CONVECTION_MODEL, normal_z=1.0,
                           length_flow: float = GROUND_CONVECTION_LENGTHS["length_flow"],
                           length_vertical: float = GROUND_CONVECTION_LENGTHS["length_vertical"],
                           length_horizontal: float = GROUND_CONVECTION_LENGTHS[
                               "length_horizontal"]) -> Callable:
    """Convective coefficient from one of the project's exterior correlations.

    Parameters
    ----------
    model : str
        Key of :data:`shipthermal.environment.convection.CONVECTION_MODELS` (default the
        ship's default, :data:`shipthermal.parameters.DEFAULT_CONVECTION_MODEL`).
    normal_z : float or array_like
        (N,) upward component of the surface normal, cos(slope) [-].
    length_flow, length_vertical, length_horizontal : float
        Characteristic lengths [m] (:data:`GROUND_CONVECTION_LENGTHS`).

    Returns
    -------
    callable
        ``h(temp_surface [K], temp_air [K], wind_speed [m s-1]) -> [W m-2 K-1]``.
    """
    cm = convection_model(model, "background.convection.model")

    def h(temp_surface, temp_air, wind_speed):
        return cm.h(temp_surface, temp_air,
                    ExteriorFlow(normal_z=normal_z, wind_speed=wind_speed,
                                 length_flow=length_flow, length_vertical=length_vertical,
                                 length_horizontal=length_horizontal))

    h.__doc__ = f"{cm.name}: {cm.source}"
    return h


def convection_aerodynamic(roughness_length, roughness_length_heat=None,
                           displacement_height=0.0, height_wind: float = 10.0,
                           height_temp: float | None = None, stability: bool = False,
                           pressure=101325.0) -> Callable:
    """Convective coefficient ``ρ_a c_p / r_a`` from the neutral logarithmic wind profile.

    Parameters
    ----------
    roughness_length : float or array_like
        (N,) z_0m [m] (a class's ``roughness_length``).
    roughness_length_heat : float or array_like, optional
        (N,) z_0h [m]; default z_0m / 10.
    displacement_height : float or array_like
        (N,) d [m].
    height_wind : float
        Height of the wind measurement above the surface [m].
    height_temp : float, optional
        Height of the air temperature [m]; default ``height_wind``.
    stability : bool
        Multiply the neutral coefficient by a bulk-Richardson stability factor:
        ``(1 − 16 Ri)^0.75`` unstable, ``(1 − 5 Ri)²`` stable, Ri clipped at 0.19.
    pressure : float
        [Pa] for ρ_a c_p.

    Returns
    -------
    callable
        ``h(temp_surface [K], temp_air [K], wind_speed [m s-1]) -> [W m-2 K-1]``.

    Notes
    -----
    FAO-56 eq. 4: ``r_a = ln((z_m − d)/z_0m) ln((z_h − d)/z_0h) / (k² u_z)``, k = 0.41 (with
    z_m = z_h = 2 m and the grass of FAO-56 this is r_a = 208/u_2). Calm air would give h → 0:
    the wind is floored at 0.5 m s-1 (ASSUMPTION: free convection keeps a minimum exchange;
    the floor FAO-56 advises for very low measured winds). Stability (optional, ASSUMPTION:
    the usual bulk-Richardson shortcut, ζ ≈ Ri): unstable, Dyer's (1974) φ_m = (1 − 16ζ)^-1/4
    and φ_h = (1 − 16ζ)^-1/2 give the factor (1 − 16 Ri)^3/4; stable, Webb's (1970)
    φ = 1 + 5ζ with ζ = Ri/(1 − 5 Ri) gives (1 − 5 Ri)²; Ri = g z (T_air − T_s) /
    (T_air u²), evaluated with the surface temperature at the start of the step.
    """
    z0m = np.asarray(roughness_length, dtype=float)
    z0h = z0m / 10.0 if roughness_length_heat is None else np.asarray(roughness_length_heat,
                                                                         dtype=float)
    d = np.asarray(displacement_height, dtype=float)
    zt = height_wind if height_temp is None else height_temp
    check_range("convection.height_wind", height_wind, 0.1, 200.0, "m")
    if np.any(height_wind - d <= z0m) or np.any(zt - d <= z0h):
        raise InputError("convection.height_wind", height_wind,
                         "must exceed displacement height + roughness length")
    log_product = np.log((height_wind - d) / z0m) * np.log((zt - d) / z0h)

    def h(temp_surface, temp_air, wind_speed):
        u = np.maximum(np.asarray(wind_speed, dtype=float), 0.5)
        hn = air_heat_capacity(temp_air, pressure) * VON_KARMAN ** 2 * u / log_product
        if not stability:
            return hn
        ta = np.asarray(temp_air, dtype=float)
        ri = 9.80665 * zt * (ta - np.asarray(temp_surface)) / (ta * u * u)
        ri = np.minimum(ri, 0.19)
        factor = np.where(ri < 0.0, (1.0 - 16.0 * np.minimum(ri, 0.0)) ** 0.75,
                          (1.0 - 5.0 * np.maximum(ri, 0.0)) ** 2)
        return hn * factor

    # what the solver's compiled loop needs to compute the same coefficient
    # (:func:`.kernels._h_aerodynamic`)
    h.aerodynamic = (log_product, zt, stability, pressure)
    return h


def convection_linear(a: float, b: float) -> Callable:
    """``h = a + b v`` [W m-2 K-1] (e.g. ISO 6946 a = b = 4, or a user curve of EnergyPlus).

    Parameters
    ----------
    a : float
        [W m-2 K-1].
    b : float
        [J m-3 K-1].
    """
    def h(temp_surface, temp_air, wind_speed):
        return a + b * np.asarray(wind_speed, dtype=float) + 0.0 * np.asarray(temp_surface)

    return h
