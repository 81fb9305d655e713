"""Per-face boundary forcing of a ship for a diurnal run (a periodic design day or a weather
record).

This package wires the environment (:mod:`shipthermal.environment`), the ray tracer
(:mod:`shipthermal.raytrace`) and the ship (:mod:`shipthermal.geometry`) into boundary
conditions in the solver's format (:mod:`shipthermal.conditions`, ``docs/SOLVER-API.md``).
It adds no new physics kernel: it evaluates the published ones once, on a table of times
of one design day, and serves them to the solver by interpolation.

Data flow::

    ship surface (outer boundary faces of the cell graph)
        ├─ Embree: lit fraction per face and sun direction (cached per direction)
        ├─ Embree: view factors F_sky, F_sea, F_ij (reciprocity imposed)
    environment.at(table times)  ──►  tables (n_times, n_faces) of absorbed short-wave,
                                      convection coefficients; scalar series of T_air,
                                      L_down, sea long-wave, SST
    ShipForcing.conditions()      ──►  {patch: SurfaceBalance / Convection} with f(t)
    ShipForcing.radiative_exchange() ──► (bfaces, A_i ε_i ε_j F_ij) for RadiativeExchange

:func:`build_ship_forcing` is a chain of small stages: :func:`surface_properties` (forced
patches, part, medium, optics) → :func:`flow_lengths` (convection lengths per part) →
convection (:func:`wetted_hull_convection`, :func:`air_convection` with a model of
:data:`~shipthermal.environment.convection.CONVECTION_MODELS` chosen by
``ForcingSettings.convection``, the inner films) → the tables.

The package, one job per module:

* :mod:`.tables` — table times of a design day or a weather record, interpolation;
* :mod:`.tracing` — the tracer, view factors and lit-fraction cache of the outer surface;
* :mod:`.surface` — forced patches, part and medium of every face, optics per part;
* :mod:`.convection` — convection of the air, wetted and inner faces with the
  quasi-steady surface estimate;
* :mod:`.shortwave` — absorbed short-wave of the outer faces;
* :mod:`.ship_forcing` — :class:`ShipForcing`, the tables served to the solver;
* :mod:`.build` — :func:`build_ship_forcing` and its :class:`ForcingSettings`.

Physics per outer face i (normal n_i, area A_i, solar absorptivity α_i, long-wave
emissivity ε_i), at time t with sun direction s in the ship frame:

* **absorbed short-wave** [W m-2]
  ``q_i = α_i (E0_i + E1_i)`` with the incident irradiance
  ``E0_i = DNI·max(n_i·s, 0)·lit_i + DHI·F_sky,i + SW_sea↑·F_sea,i``
  (direct beam with traced self-shadowing; isotropic diffuse sky — the "isotropic sky"
  model, Liu & Jordan 1963 — seen through the traced sky view factor; sea-reflected
  short-wave as a Lambertian sea of radiosity SW_sea↑, reciprocity A_sea F_sea→i =
  A_i F_i→sea) and the first diffuse bounce off other ship faces
  ``E1_i = Σ_j F_ij (1 − α_j) E0_j`` (``ship_reflection=True``). The ship's shadow on the
  sea is not subtracted from SW_sea↑.
* **incident long-wave** from the environment ``L_env,i = F_sky,i L↓ + F_sea,i L_sea↑``.
  ``L↓`` is the hemispherical downwelling flux on a horizontal surface; using it with the
  sky view factor treats the sky radiance as isotropic. For vertical faces this is the
  isotropic approximation: the real clear sky is brighter near the horizon, so vertical
  faces receive somewhat more than ``F_sky L↓`` (a few to ~10 % of the sky part).
* **long-wave exchange between ship faces** (grey, diffuse, one absorption): the pair
  :meth:`ShipForcing.radiative_exchange` gives ``R_ij = A_i ε_i ε_j F_ij``. With it, the
  surface balance must only carry the environment share of the face's emission, so
  :meth:`ShipForcing.conditions` (``with_exchange=True``) sets the balance's emissivity to
  ``ε_i (F_sky,i + F_sea,i)`` and its ``longwave_in`` to ``L_env,i / (F_sky,i + F_sea,i)``:
  then ``ε_eff (L_in − σT⁴) + σ Σ_j R_ij (T_j⁴ − T_i⁴) / A_i`` is the face's net
  long-wave, conserving energy between faces exactly (the part (1 − ε_j) of i's emission
  reflected by j is taken to return to i). Without the exchange (``with_exchange=False``) the
  other ship faces a face sees are replaced by black bodies at the air temperature.
* **convection, air faces**: a model of
  :data:`~shipthermal.environment.convection.CONVECTION_MODELS` per part (default
  :data:`~shipthermal.parameters.DEFAULT_CONVECTION_MODEL`, the flat plate turbulent from
  its leading edge, forced + natural convection combined by Churchill 1977, n = 3;
  docs/CONVECTION.md).
  Forced: flat plate at the apparent wind at the face's height (true wind brought from
  10 m to the centroid height by the neutral log profile, then the ship's velocity
  subtracted); flow length = extent of the part's horizontal bounding box along the
  apparent wind. Natural: per face tilt (``n_z``), plate height = the part's height,
  ``A/P`` of the part's horizontal bounding box.
* **convection, wetted faces**: :func:`~shipthermal.environment.convection.h_hull_water`
  to sea water at the SST (ship speed + ``current_speed``, waterline length, draught);
  no sun, no long-wave.
* **inner faces**: convection to the compartment air ``ship.compartment_temperature``
  per part, ISO 6946:2017 Annex C coefficients *including* the linearised interior
  radiation ``ε 4σT_m³`` (interior radiation is not modelled otherwise), or a constant
  ``interior_h``.

Convection coefficients depend on the surface temperature (natural convection, film
properties, the heat-flow direction of ISO 6946). The air faces' coefficient is a forced
part, tabulated, and a law of the surface temperature
(:class:`~shipthermal.conditions.ConvectionLaw`, :meth:`ShipForcing.convection_law`) that
the solver evaluates at the surface temperature it solves for. What the tables still need
of the surface temperature, the air properties of the film (flat-plate models) and the
inner faces' heat-flow direction, comes from a quasi-steady estimate: the root of the face's
energy balance with the heat capacity neglected and conduction through the part's layup to
the compartment air (Newton, 3 steps). A thin plate follows that estimate within a few
kelvin; the film's properties change by ~0.3 % per kelvin.

Tables. Everything that varies per face and time is tabulated at the given ``times``
(seconds after local midnight, one periodic design day) as ``(n_times, n_faces)`` arrays
(float32 by default: 7 significant digits, far below the model's accuracy) and linearly
interpolated between table times, with ``t`` folded modulo 86 400 s, so day k of a
spin-up sees exactly day 0's forcing. Values are exact at the table times.
"""

from .build import ForcingSettings, build_ship_forcing
from .convection import (INTERIOR_EMISSIVITY, AirConvection, BackSide, FlowLengths,
                         air_convection, air_convection_models, back_side, exterior_terms,
                         flow_lengths, quasi_steady_surface_temperature,
                         wetted_hull_convection)
from .ship_forcing import ShipForcing
from .surface import SurfaceProperties, part_choices, part_values, surface_properties
from .tables import MAX_TABLE_GAP, PeriodicTable, RecordTable
from .tracing import TracedShip, trace_ship

__all__ = ["MAX_TABLE_GAP", "INTERIOR_EMISSIVITY", "TracedShip", "ShipForcing", "trace_ship",
           "build_ship_forcing", "ForcingSettings", "part_values",
           "quasi_steady_surface_temperature", "PeriodicTable", "RecordTable",
           "SurfaceProperties", "surface_properties", "FlowLengths", "flow_lengths",
           "BackSide", "back_side", "wetted_hull_convection", "air_convection",
           "AirConvection", "air_convection_models", "exterior_terms", "part_choices"]
