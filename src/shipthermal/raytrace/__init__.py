"""Ray tracing for the thermal boundary conditions: direct-sun lit fractions and view factors.

Two tracers answer the same calls (``intersects_first``, ``any_hit``): :class:`EmbreeTracer`
(Embree through embreex, float32) and :class:`NumbaTracer` (an independent float64 numba BVH
used as fallback and to cross-check Embree). Build one with :func:`make_tracer`, then

* :func:`sun_lit_fraction` – lit fraction of every face for many sun directions at once;
* :func:`view_factors` – sky / sea / face-to-face view factors (sparse) with standard errors;
* :func:`shadow_area_on_plane` – a mesh's shadow area on a horizontal plane.
"""

from shipthermal.raytrace.sunlit import (ReceiverPlane, SunLit, shadow_area_on_plane,
                                         sun_lit_fraction)
from shipthermal.raytrace.tracers import (RAY_OFFSET_FACTOR, EmbreeTracer, NumbaTracer,
                                          has_embree, make_tracer, ray_offset)
from shipthermal.raytrace.viewfactors import ViewFactors, symmetrize, view_factors

__all__ = ["RAY_OFFSET_FACTOR", "EmbreeTracer", "NumbaTracer", "has_embree", "make_tracer",
           "ray_offset", "ReceiverPlane", "SunLit", "sun_lit_fraction", "shadow_area_on_plane",
           "ViewFactors", "view_factors", "symmetrize"]
