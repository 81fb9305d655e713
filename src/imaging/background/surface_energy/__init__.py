"""Surface energy balance of land background pixels over layered columns.

Each land pixel is a one-dimensional column (layers of :mod:`.surface_classes`, surface
first) whose top face carries the surface energy balance

    S_abs + ε L↓ − ε σ T_s⁴ − h (T_s − T_air) − λE(T_s) − G = 0,

and whose bottom is a fixed deep-ground temperature (``'deep'``) or an indoor air space reached
through a film coefficient (``'room'``). Many columns are advanced together on a uniform time
grid.

Modules: ``air`` (moist air, latent heat), ``convection`` (convective coefficients),
``columns`` (meshes and columns), ``forcing`` (forcing on a time grid, tilted pixels),
``kernels`` (the step kernels), ``solver`` (the time loop and its result).

Pieces, each a function:

* :func:`column_mesh` — finite volumes refined toward the surface (geometric growth), layer
  interfaces on cell faces, harmonic-mean (series) face conductances;
* :func:`shortwave_on_tilted`, :func:`sky_view_factor`, :func:`longwave_incoming` — the
  forcing of a tilted pixel (pvlib's transposition; isotropic sky view (1 + cos s) / 2);
* :func:`convection_correlation`, :func:`convection_aerodynamic`, :func:`convection_linear` —
  convective coefficients ``h(temp_surface, temp_air, wind_speed)``;
* :func:`saturation_vapour_pressure`, :func:`latent_heat_flux` — Penman–Monteith resistance
  form;
* :func:`solve_surface_energy` — the time loop (periodic design day or record with a periodic
  spin-up on its first day), with a numba kernel (:func:`.kernels._step_numba`: columns in
  parallel, Thomas algorithm per column; with the log-law convection whole spans of steps in
  one compiled call, :func:`.kernels._span_numba`) and a plain numpy reference
  (:func:`.kernels._step_reference`) doing the same arithmetic.

Time discretisation: θ-scheme, backward Euler by default (θ = 1). The surface node has no
heat capacity, so its balance is an algebraic constraint enforced at the new time level;
backward Euler is L-stable, so the stiff modes of the thin top cells (time constants of
seconds against 300 s steps) are damped instead of ringing as under Crank–Nicolson (θ = ½,
A- but not L-stable), which is offered for the second-order accuracy when the time step
resolves the top cells. Within a step the surface balance is solved by Newton on the Schur
complement of the column (T⁴ and the latent term at the new temperature, never lagged); the
convective coefficient is evaluated with the surface temperature at the start of the step.
"""

from .air import (GAS_CONSTANT_DRY_AIR, LATENT_HEAT_VAPORISATION, SPECIFIC_HEAT_AIR, VON_KARMAN,
                  air_heat_capacity, latent_heat_flux, psychrometric_constant,
                  saturation_vapour_pressure, saturation_vapour_pressure_slope)
from .columns import ColumnMesh, Columns, build_columns, column_mesh
from .convection import (GROUND_CONVECTION_LENGTHS, convection_aerodynamic,
                         convection_correlation, convection_linear)
from .forcing import (SurfaceForcing, forcing_from_environment, longwave_incoming,
                      shortwave_on_tilted, sky_view_factor)
from .solver import SCHEMES, SurfaceEnergyResult, solve_surface_energy

__all__ = [
    "LATENT_HEAT_VAPORISATION",
    "SPECIFIC_HEAT_AIR",
    "GAS_CONSTANT_DRY_AIR",
    "VON_KARMAN",
    "GROUND_CONVECTION_LENGTHS",
    "SCHEMES",
    "ColumnMesh",
    "column_mesh",
    "Columns",
    "build_columns",
    "SurfaceForcing",
    "SurfaceEnergyResult",
    "saturation_vapour_pressure",
    "saturation_vapour_pressure_slope",
    "air_heat_capacity",
    "psychrometric_constant",
    "latent_heat_flux",
    "convection_correlation",
    "convection_aerodynamic",
    "convection_linear",
    "sky_view_factor",
    "shortwave_on_tilted",
    "longwave_incoming",
    "forcing_from_environment",
    "solve_surface_energy",
]
