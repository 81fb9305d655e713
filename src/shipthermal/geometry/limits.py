"""How large a ship mesh may become, checked before it is built.

A target edge length that asks for tens of millions of triangles does not fail at once: it
runs for minutes, fills the memory and dies in the mesher. The number of triangles follows
from the area and the edge length, so it is estimated and refused before any meshing.
"""

from __future__ import annotations

import math

from ..errors import InputError

__all__ = ["MAX_SURFACE_FACES", "BUILTIN_AREA_FACTOR", "expected_faces",
           "builtin_area_bound", "check_surface_size"]

MAX_SURFACE_FACES = 2_000_000
"""Most surface triangles a run may have. ASSUMPTION sized on a workstation's memory: the
default frigate has 59 694 triangles at 0.5 m; the view factors alone keep up to
``solver.rays_per_face`` (256) entries per triangle, 2 million × 256 × 12 bytes ≈ 6 GB,
before the cell graph, the sun-lit fractions and the outputs."""

BUILTIN_AREA_FACTOR = 1.6
"""DERIVED: surface area of the built-in ships over ``length · (beam + 2 draught + 2
freeboard)``: frigate 6264 m2 (1.40), patrol boat 1496 m2 (1.28), cargo ship 16 607 m2
(1.51) at their default dimensions; 1.6 bounds them from above."""


def expected_faces(area_m2: float, edge_length: float) -> float:
    """Triangles of a surface of ``area_m2`` [m2] meshed at ``edge_length`` [m]: the area
    over that of an equilateral triangle (the built-in frigate: 57 900 estimated, 59 694
    built)."""
    return float(area_m2) / (math.sqrt(3.0) / 4.0 * float(edge_length) ** 2)


def builtin_area_bound(length: float, beam: float, draught: float, freeboard: float) -> float:
    """An upper bound of a built-in ship's surface area [m2] from its particulars [m]."""
    return BUILTIN_AREA_FACTOR * length * (beam + 2.0 * draught + 2.0 * freeboard)


def check_surface_size(area_m2: float, edge_length: float, field: str = "ship.edge_length") -> None:
    """Refuse an edge length that would give more than :data:`MAX_SURFACE_FACES` triangles.

    Parameters
    ----------
    area_m2 : float
        Surface area of the ship [m2].
    edge_length : float
        Target edge length [m].
    field : str
        Key named in the message.
    """
    n = expected_faces(area_m2, edge_length)
    if n > MAX_SURFACE_FACES:
        smallest = math.sqrt(area_m2 / (math.sqrt(3.0) / 4.0 * MAX_SURFACE_FACES))
        raise InputError(field, edge_length, f"would give about {n:,.0f} surface triangles "
                         f"over about {area_m2:,.0f} m2 of ship surface, more than the "
                         f"{MAX_SURFACE_FACES:,} a run may have (memory)",
                         f"Use {field} >= {math.ceil(smallest * 1000) / 1000:g} m")
