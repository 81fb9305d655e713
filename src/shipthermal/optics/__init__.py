"""The optics both stages share: one home for each law of light at a surface.

* :mod:`~shipthermal.optics.water` — water's complex refractive index (Hale & Querry 1973),
  the Fresnel reflectance, the flat sea's emissivity and the thermal stage's rough-sea
  hemispherical emissivity;
* :mod:`~shipthermal.optics.responses` — sensor spectral responses: the paper's rectangles,
  real instruments' bands, a user's response file;
* :mod:`~shipthermal.optics.planck` — Planck's law, band radiance over a response, its
  inverse (brightness temperature), fast band-radiance tables;
* :mod:`~shipthermal.optics.sea` — the sea's band emissivity, flat and wind-roughened
  (consistent with the Cox-Munk reflectance);
* :mod:`~shipthermal.optics.brdf` — BRDFs (Cox-Munk sea, RPV land, Cook-Torrance paint) and
  their directional albedo;
* :mod:`~shipthermal.optics.quadrature` — the quadrature rules behind them.

The thermal stage (:mod:`shipthermal.environment`: the sea's long-wave) and the imaging
(:mod:`imaging.radiometry`, the renderer, the background, the atmosphere's band integrals)
import these from here; this package imports no other room of the thermal stage.

The names of :mod:`~shipthermal.optics.water` are re-exported here (``from shipthermal.optics
import fresnel_reflectance``); the other modules load on first use (scipy's special
functions are not needed by the thermal stage).
"""

from __future__ import annotations

from .water import (ROUGH_SEA_HEMISPHERICAL_EMISSIVITY, ROUGH_SEA_WIND_NODES,
                    WATER_INDEX_HALE_QUERRY, WATER_REFRACTIVE_INDEX_10UM, fresnel_reflectance,
                    sea_emissivity_angular, sea_emissivity_hemispherical, sea_emissivity_rough,
                    water_refractive_index)

__all__ = [
    "WATER_INDEX_HALE_QUERRY",
    "water_refractive_index",
    "WATER_REFRACTIVE_INDEX_10UM",
    "fresnel_reflectance",
    "sea_emissivity_angular",
    "sea_emissivity_hemispherical",
    "ROUGH_SEA_WIND_NODES",
    "ROUGH_SEA_HEMISPHERICAL_EMISSIVITY",
    "sea_emissivity_rough",
]
