"""Convective heat-transfer coefficients for ship faces.

Pure vectorised functions over per-face arrays:

* fluid properties of air (film temperature) and sea water (:mod:`.fluids`),
* the wind relative to a moving ship (apparent wind), the wind at a height (:mod:`.wind`),
* forced convection over flat plates (laminar, turbulent, mixed boundary layer),
  natural convection for vertical, horizontal (facing up / down) and tilted plates,
  mixed forced + natural convection (Churchill 1977, n = 3), wetted hull to sea water
  (:mod:`.plates`),
* the building-envelope correlations of the EnergyPlus family (DOE-2, TARP, MoWiTT,
  McAdams, ISO 6946) (:mod:`.envelope`),
* inner faces to compartment air (ISO 6946 or natural) (:mod:`.interior`).

The exterior models of :data:`CONVECTION_MODELS` give their coefficient as a forced part and
a law of the surface temperature (:class:`shipthermal.conditions.ConvectionLaw`), which the
solver evaluates at the surface temperature it solves for (:mod:`.models`).

Temperatures in K, speeds in m/s, lengths in m, coefficients h in W m-2 K-1.
"""

from __future__ import annotations

from shipthermal.parameters import DEFAULT_CONVECTION_MODEL

from . import models
from .envelope import (ASHRAE_VERTICAL, MCADAMS, MOWITT_FORCED, MOWITT_NATURAL,
                       ROUGHNESS_MULTIPLIERS, SPARROW_FORCED, WALTON_STABLE, WALTON_UNSTABLE,
                       WINDWARD_HORIZONTAL_COS, h_exterior_doe2, h_exterior_iso6946,
                       h_exterior_mowitt, h_exterior_tarp, h_natural_walton, is_windward,
                       roughness_multiplier)
from .fluids import G, FluidProperties, air_properties, seawater_properties
from .interior import ISO6946_INTERIOR_CONVECTION, h_interior, h_interior_iso6946
from .models import CONVECTION_MODELS, ConvectionModel, ExteriorFlow, convection_model
from .plates import (combine_mixed, h_exterior_air, h_exterior_air_turbulent, h_forced,
                     h_hull_water, h_natural, nusselt_forced_flat_plate,
                     nusselt_horizontal_plate, nusselt_vertical_plate, rayleigh, reynolds)
from .wind import SEA_ROUGHNESS_LENGTH, relative_wind, wind_speed_at_height

_MODEL_TERMS = models._MODEL_TERMS

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
    "WINDWARD_HORIZONTAL_COS",
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
