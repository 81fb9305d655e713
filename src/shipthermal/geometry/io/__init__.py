"""User ship meshes: reading, part maps, checks and optional repair; writing ship files.

A user ship is either **one file per part** (``{"hull": "hull.stl", "deck": "deck.stl",
"superstructure": "sup.obj"}``) or **one mesh plus a part map**: a per-triangle array of
part indices or names, a JSON file / dict of face ranges ``{"deck": [[0, 1200]], ...}``, or a
``part`` cell array inside a VTK file. Units must be declared (``'m'`` or ``'mm'``).

The surface must be a closed, consistently wound triangulation with outward normals. Checks
(each raising :class:`~shipthermal.errors.InputError` with what to do):

* scale sanity — a 130 000 m or 1 cm ship is a units mistake, not a ship;
* axes — the longest dimension must be x (bow +x, y port, z up);
* degenerate (zero-area) and duplicate triangles — error, or with ``clean=True`` collinear
  needles at T-junctions are flipped into their neighbour (surface stays closed, area
  unchanged) and the rest dropped (counted in the report);
* watertightness — open edges (gaps, a missing face) and edges shared by more than two
  triangles; ``repair='tetwild'`` remeshes through pytetwild instead (area and volume
  change reported);
* self-intersections — e.g. overlapping solids exported without a union: error, or
  ``repair='tetwild'``;
* orientation — inconsistent winding or inward normals (signed volume < 0): error, or
  fixed with ``fix_normals=True`` (reported).

A part named ``hull`` is split exactly at the waterline into ``hull_wetted``/``hull_dry``.

Modules: :mod:`.load` (surface files, units), :mod:`.part_map` (part maps),
:mod:`.sources` (the ship's files and part labels as loaded), :mod:`.checks`
(:func:`check_surface`), :mod:`.repairs` (cached repair, outside test), :mod:`.read`
(:func:`read_ship` and its :class:`ReadShipSettings`), :mod:`.write` (:func:`write_ship`).
"""

from ..cad import SHIP_LENGTH_RANGE
from .checks import check_surface
from .load import MESH_EXTENSIONS, PYVISTA_EXTENSIONS, TRIMESH_EXTENSIONS, UNITS, load_surface
from .part_map import read_part_map
from .read import ReadShipSettings, read_ship
from .write import write_ship

__all__ = ["UNITS", "SHIP_LENGTH_RANGE", "TRIMESH_EXTENSIONS", "PYVISTA_EXTENSIONS",
           "MESH_EXTENSIONS", "load_surface", "read_part_map", "check_surface",
           "ReadShipSettings", "read_ship", "write_ship"]
