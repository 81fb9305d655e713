"""Ship geometry: built-in parametric ships, user meshes, named parts and plate layups.

Data flow: a :class:`ShipGeometry` (closed triangulated surface, outward normals, a part per
triangle, a layup and a compartment air temperature per part) comes from a built-in
generator (:func:`frigate` — the default —, :func:`patrol_boat`, :func:`cargo_ship`) or from
a user mesh (:func:`read_ship`, its options in :class:`ReadShipSettings`);
:func:`build_ship_mesh` remeshes it to a target edge length and builds the finite-volume cell
graph (multilayer shells, or tetrahedra for an all-solid verification model)::

    from shipthermal.geometry import frigate, build_ship_mesh
    ship = frigate()                       # 132 m, ~60 000 triangles at 0.5 m
    graph, report = build_ship_mesh(ship)  # shell cells through each part's layup

Coordinates: x forward (bow +x), y to port, z up, z = 0 at the waterline, origin amidships.
"""

from .io import ReadShipSettings, read_ship, write_ship
from .layups import compartment_temperatures, default_layups, outer_media
from .parts import MAIN_PARTS, main_part, split_at_waterline
from .pictures import render_parts_png, write_parts_vtu
from .remesh import build_ship_mesh, remesh_ship
from .surface_ops import surface_quality
from .ship import (BUILTIN_SHIPS, DEFAULT_EDGE_LENGTH, Block, ShipParameters, build_ship,
                   cargo_ship, frigate, patrol_boat)
from .ship_geometry import ShipGeometry

__all__ = ["ShipGeometry", "ShipParameters", "Block", "build_ship", "frigate", "patrol_boat",
           "cargo_ship", "BUILTIN_SHIPS", "DEFAULT_EDGE_LENGTH", "MAIN_PARTS", "main_part",
           "split_at_waterline", "default_layups", "compartment_temperatures", "outer_media",
           "read_ship", "ReadShipSettings", "write_ship", "build_ship_mesh", "remesh_ship",
           "surface_quality", "render_parts_png", "write_parts_vtu"]
