"""Ship geometry: built-in parametric ships, user meshes, named parts and plate layups.

Data flow: a :class:`ShipGeometry` (closed triangulated surface, outward normals, a part per
triangle, a layup and a compartment air temperature per part) comes from a built-in
generator (:func:`frigate`, :func:`patrol_boat`, :func:`cargo_ship`) or from a user mesh
(:func:`read_ship`); :func:`build_ship_mesh` remeshes it to a target edge length and builds
the finite-volume cell graph (multilayer shells, or tetrahedra for solid parts).
"""

from .layups import compartment_temperatures, default_layups, outer_media
from .parts import MAIN_PARTS, main_part, split_at_waterline
from .ship import (BUILTIN_SHIPS, DEFAULT_EDGE_LENGTH, Block, ShipGeometry, ShipParameters,
                   build_ship, cargo_ship, frigate, patrol_boat)

__all__ = ["ShipGeometry", "ShipParameters", "Block", "build_ship", "frigate", "patrol_boat",
           "cargo_ship", "BUILTIN_SHIPS", "DEFAULT_EDGE_LENGTH", "MAIN_PARTS", "main_part",
           "split_at_waterline", "default_layups", "compartment_temperatures", "outer_media"]
