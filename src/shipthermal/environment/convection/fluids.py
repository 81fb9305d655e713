"""Properties of the two fluids a ship's faces exchange heat with: air at the film
temperature and sea water.

Temperatures in K, pressure in Pa.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from shipthermal.units import ZERO_CELSIUS

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
