"""The port background as physics: every pixel a surface energy balance under the ship's sky.

The paper's background (:mod:`.background`) extends one Landsat overpass through the day
with a same-day kriged met grid and a terrain regression; it exists only where such a grid
exists, and the built-in port carried its design days' climate wherever it was placed.
Here the background follows the run's one :class:`shipthermal.environment.Environment` —
the same sun, sky long-wave, air, humidity, wind, cloud and sea as the ship — at any site,
date and weather record:

* **land pixels** (vegetation, land, building, and classes users add) are layered columns
  (:mod:`.surface_classes`, :mod:`.surface_energy`): absorbed short-wave on the pixel's own
  slope and aspect, long-wave exchange with the sky it sees and with the terrain around it,
  convection, latent heat where the class evaporates, conduction into the substrate;
* **water pixels** are the weather's sea at its skin temperature (bulk + diurnal warm layer
  − cool skin, :mod:`shipthermal.environment.sea_skin`): the very sea the ship floats on;
* **terrain**: each pixel's slope and aspect (DEM or the synthetic hills) set its solar
  incidence (pvlib's plane-of-array irradiance) and its sky view ``(1 + cos s)/2``; the rest
  of its hemisphere is terrain taken at the air temperature (ASSUMPTION: no terrain
  horizon shading, no building shadows).

**Columns, not pixels.** A 1000 x 1000 scene has a million pixels but few distinct columns:
pixels are grouped by class and orientation (slope bins of :data:`SLOPE_EDGES_DEG` x
:data:`ASPECT_SECTORS` aspect sectors, the bin's mean slope and circular-mean aspect), and
each group is solved at :data:`ALBEDO_SAMPLES` short-wave albedos spanning its class's
range; a pixel's temperature is the linear interpolation between the two columns whose
albedos bracket its own. The surface temperature is close to linear in the albedo (the
absorbed short-wave is), and the interpolation and orientation-binning errors are measured
in the tests.

**Anchoring on a scene** (Landsat, :func:`ground_from_overpass`): each land pixel's albedo
is *fitted* within its class's range so that the model reproduces the scene's LST at the
overpass instant (a labelled calibration; everything else is the class table). What the fit
cannot reach (LST hotter than the darkest or colder than the brightest allowed surface) is
the pixel's residual, carried through the day as :data:`RESIDUAL_MODES` says and reported
per class with the fitted albedos' spread. Water is never fitted: its spatial pattern at the
overpass (LST minus the scene's median water LST) is kept as a fixed anomaly on the modelled
skin temperature, and the scene's median water against the model is reported as a check of
the weather's sea temperature. Without a scene (the synthetic port, a user class raster) the
albedo is the class value (the synthetic port: with its reflectance texture) and every product
says so.

Modules: ``ground`` (what is known of the ground: classes, terrain, albedo, the scene),
``columns`` (class x orientation groups, their forcing and solve), ``anchoring`` (the fit
on a scene, the water's pattern), ``result`` (:class:`PhysicalBackground`), ``build``
(:func:`build_physical_background`).
"""

from ...parameters import RESIDUAL_MODES
from .anchoring import MAX_SCENE_DAYS, ClassFit
from .build import (COLUMN_STEP_S, LONG_RECORD_DAYS, LONG_RECORD_STEP_S,
                    build_physical_background)
from .columns import (ALBEDO_SAMPLES, CONDUCTANCE_SAMPLES, SLOPE_EDGES_DEG, land_convection,
                      orientation_bins)
from .ground import (GroundCover, Observation, broadband_albedo, ground_from_overpass,
                     ground_from_synthetic)
from .result import PhysicalBackground

__all__ = ["GroundCover", "Observation", "ClassFit", "PhysicalBackground", "build_physical_background",
           "ground_from_synthetic", "ground_from_overpass", "broadband_albedo",
           "orientation_bins", "ALBEDO_SAMPLES", "CONDUCTANCE_SAMPLES", "SLOPE_EDGES_DEG", "RESIDUAL_MODES",
           "MAX_SCENE_DAYS", "COLUMN_STEP_S", "LONG_RECORD_DAYS", "LONG_RECORD_STEP_S",
           "land_convection"]

