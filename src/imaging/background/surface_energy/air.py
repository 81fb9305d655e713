"""Moist air and the latent heat flux of a land surface (FAO-56 constants and the
Penman–Monteith resistance form)."""

from __future__ import annotations


import numpy as np

from shipthermal.units import ZERO_CELSIUS



# ---------------------------------------------------------------------------------------------
# Constants (FAO-56 [2] of :mod:`.surface_classes`, so that its eq. 3 is reproduced exactly)
# ---------------------------------------------------------------------------------------------
LATENT_HEAT_VAPORISATION = 2.45e6
"""λ [J kg-1]: FAO-56 eq. 8 (value at about 20 °C; it falls by 2.4 % from 0 to 40 °C)."""
SPECIFIC_HEAT_AIR = 1013.0
"""c_p of moist air [J kg-1 K-1]: FAO-56 eq. 8."""
GAS_CONSTANT_DRY_AIR = 287.0
"""R [J kg-1 K-1]: FAO-56 eq. 3 notes (ρ_a = P / (1.01 T R), 1.01 T the virtual temperature)."""
RATIO_MOLECULAR_WEIGHT = 0.622
"""ε = M_w / M_d [-]: FAO-56 eq. 8."""
VON_KARMAN = 0.41
"""k [-]: FAO-56 eq. 4."""
_ES0, _ES_A, _ES_B = 610.8, 17.27, 237.3  # FAO-56 eq. 11 (Tetens): e° = 610.8 exp(a T/(T + b)) Pa

# ---------------------------------------------------------------------------------------------
# Moist air and latent heat
# ---------------------------------------------------------------------------------------------
def saturation_vapour_pressure(temp):
    """Saturation vapour pressure over water [Pa].

    Parameters
    ----------
    temp : array_like
        Temperature [K].

    Notes
    -----
    FAO-56 eq. 11 (Tetens 1930): e° = 610.8 exp(17.27 T_c / (T_c + 237.3)) Pa, T_c in °C.
    """
    tc = np.asarray(temp, dtype=float) - ZERO_CELSIUS
    return _ES0 * np.exp(_ES_A * tc / (tc + _ES_B))


def saturation_vapour_pressure_slope(temp):
    """d e°/dT [Pa K-1] of :func:`saturation_vapour_pressure` (exact derivative; FAO-56
    eq. 13 rounds 17.27 × 237.3 = 4098.171 to 4098).

    Parameters
    ----------
    temp : array_like
        [K].
    """
    tc = np.asarray(temp, dtype=float) - ZERO_CELSIUS
    return saturation_vapour_pressure(temp) * (_ES_A * _ES_B) / ((tc + _ES_B) * (tc + _ES_B))


def air_heat_capacity(temp_air, pressure=101325.0):
    """Volumetric heat capacity of air ρ_a c_p [J m-3 K-1].

    Parameters
    ----------
    temp_air : array_like
        [K].
    pressure : array_like
        [Pa].

    Notes
    -----
    FAO-56 eq. 3 notes: ρ_a = P / (1.01 T R), R = 287 J kg-1 K-1; c_p = 1013 J kg-1 K-1.
    """
    return SPECIFIC_HEAT_AIR * np.asarray(pressure, dtype=float) / (
        1.01 * GAS_CONSTANT_DRY_AIR * np.asarray(temp_air, dtype=float))


def psychrometric_constant(pressure=101325.0):
    """γ = c_p P / (ε λ) [Pa K-1] (FAO-56 eq. 8).

    Parameters
    ----------
    pressure : array_like
        [Pa].
    """
    return SPECIFIC_HEAT_AIR * np.asarray(pressure, dtype=float) / (
        RATIO_MOLECULAR_WEIGHT * LATENT_HEAT_VAPORISATION)


def latent_heat_flux(temp_surface, temp_air, relative_humidity, h_convection,
                     surface_resistance, pressure=101325.0):
    """Latent heat flux of a vegetated (or wet) surface, Penman–Monteith resistance form.

    Parameters
    ----------
    temp_surface : array_like
        [K].
    temp_air : array_like
        [K].
    relative_humidity : array_like
        [%].
    h_convection : array_like
        Convective (sensible) coefficient [W m-2 K-1]; the aerodynamic resistance is
        ``r_a = ρ_a c_p / h`` (the same for heat and vapour).
    surface_resistance : array_like
        Bulk surface resistance r_s [s m-1].
    pressure : array_like
        [Pa].

    Returns
    -------
    numpy.ndarray
        λE [W m-2], positive upward.

    Notes
    -----
    ``λE = (ρ_a c_p / γ) (e°(T_s) − e_a) / (r_a + r_s)``, e_a = RH/100 · e°(T_air): the form
    FAO-56 eq. 3 is derived from before e°(T_s) is linearised about T_air (FAO-56 ch. 2,
    after Monteith 1965). Written here as ``(ρ_a c_p/γ) h (e°(T_s) − e_a) / (ρ_a c_p + h r_s)``.
    """
    rho_cp = air_heat_capacity(temp_air, pressure)
    coef = rho_cp / psychrometric_constant(pressure) * h_convection / (
        rho_cp + np.asarray(h_convection) * surface_resistance)
    ea = np.asarray(relative_humidity) / 100.0 * saturation_vapour_pressure(temp_air)
    return coef * (saturation_vapour_pressure(temp_surface) - ea)
